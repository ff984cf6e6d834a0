// One view on screen: its live frames drawn into a canvas (letterboxed), its label, a
// stale banner (Frame.stale), and the numbers the status line shows.

export class Pane {
  constructor(container, link, view, options = {}) {
    this.link = link;
    this.view = view;
    this.el = document.createElement('div');
    this.el.className = 'pane';
    this.el.dataset.view = view;
    this.canvas = document.createElement('canvas');
    this.label = document.createElement('div');
    this.label.className = 'label';
    this.label.textContent = view;
    this.staleEl = document.createElement('div');
    this.staleEl.className = 'stale';
    this.staleEl.hidden = true;
    this.el.append(this.canvas, this.label, this.staleEl);
    if (options.hint) {
      const hint = document.createElement('div');
      hint.className = 'hint';
      hint.textContent = options.hint;
      this.el.append(hint);
    }
    container.append(this.el);
    this.frames = 0;          // received
    this.skipped = 0;         // sequence gaps: frames the daemon dropped for this client
    this.lastSequence = null;
    this.header = null;       // the newest frame's header (Frame without data)
    this.bytes = null;        // and its encoded image, for snapshots
    this.rect = null;         // where the image is drawn, in CSS pixels
    this.decoding = false;
    this.next = null;
    this.fpsWindow = [];
    this.channel = null;
  }

  async start(rateHz) {
    this.channel = await this.link.subscribe(this.view, { max_rate_hz: rateHz, quality: 80, stale_frames: true },
      (header, bytes, error) => this.onFrame(header, bytes, error));
  }

  async stop() {
    const channel = this.channel;
    this.channel = null;
    this.el.remove();
    if (channel !== null) await this.link.unsubscribe(channel).catch(() => {});
  }

  onFrame(header, bytes, error) {
    if (!header) {
      this.showStale('stream ended: ' + (error ? error.message : ''));
      return;
    }
    this.frames++;
    const seq = Number(header.sequence || 0);
    if (!header.stale && this.lastSequence !== null && seq > this.lastSequence + 1) {
      this.skipped += seq - this.lastSequence - 1;
    }
    if (!header.stale) this.lastSequence = seq;
    const now = performance.now();
    this.fpsWindow.push(now);
    while (this.fpsWindow.length && this.fpsWindow[0] < now - 2000) this.fpsWindow.shift();
    this.header = header;
    this.bytes = bytes;
    this.showStale(header.stale ? (header.staleReason || 'no new images') : null);
    // Only the newest frame is decoded; frames arriving during a decode replace each other.
    this.next = { header, bytes };
    if (!this.decoding) this.decode();
  }

  async decode() {
    this.decoding = true;
    while (this.next) {
      const { header, bytes } = this.next;
      this.next = null;
      try {
        const type = header.encoding === 'PNG' ? 'image/png' : 'image/jpeg';
        const bitmap = await createImageBitmap(new Blob([bytes], { type }));
        this.draw(bitmap);
        bitmap.close();
      } catch (e) {
        console.warn('frame of', this.view, 'not decoded:', e);
      }
    }
    this.decoding = false;
  }

  draw(bitmap) {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.el.clientWidth * dpr));
    const h = Math.max(1, Math.round(this.el.clientHeight * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    const scale = Math.min(w / bitmap.width, h / bitmap.height);
    const dw = bitmap.width * scale;
    const dh = bitmap.height * scale;
    const x = (w - dw) / 2;
    const y = (h - dh) / 2;
    const ctx = this.canvas.getContext('2d');
    ctx.fillStyle = '#000';
    ctx.fillRect(0, 0, w, h);
    ctx.drawImage(bitmap, x, y, dw, dh);
    this.rect = { x: x / dpr, y: y / dpr, w: dw / dpr, h: dh / dpr, iw: bitmap.width, ih: bitmap.height };
  }

  showStale(reason) {
    this.staleEl.hidden = !reason;
    if (reason) this.staleEl.textContent = 'NOT LIVE: ' + reason;
    this.el.classList.toggle('is-stale', !!reason);
  }

  // CSS pixels inside the pane -> view pixel (u, v), or null off the image.
  toImage(x, y) {
    const r = this.rect;
    if (!r) return null;
    const u = (x - r.x) / r.w * r.iw - 0.5;
    const v = (y - r.y) / r.h * r.ih - 0.5;
    if (u < -0.5 || v < -0.5 || u > r.iw - 0.5 || v > r.ih - 0.5) return null;
    return { u, v };
  }

  // Degrees per CSS pixel across the drawn image (for drags that follow the finger).
  degreesPerPixel() {
    const spec = this.header && this.header.camera && this.header.camera.spec;
    const hfov = spec && (spec.hfovDeg || spec.azimuthSpanDeg || spec.fovDeg) || 90;
    return this.rect ? hfov / this.rect.w : 0.1;
  }

  fps() { return this.fpsWindow.length < 2 ? 0 : (this.fpsWindow.length - 1) / ((this.fpsWindow.at(-1) - this.fpsWindow[0]) / 1000); }

  ageMs() {
    if (!this.header || !this.header.captureTime) return null;
    return Date.now() - Date.parse(this.header.captureTime);
  }
}
