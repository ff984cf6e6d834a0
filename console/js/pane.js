// One view on screen: its live frames drawn into a canvas (letterboxed), its label, a
// stale banner (Frame.stale), and the numbers the status line shows.
//
// Frames come over WebRTC where the browser and the link allow it (webrtc.js: RTP over UDP,
// best on a lossy Wi-Fi), else as H.264 over the WebSocket where the browser decodes it
// (WebCodecs, video.js), else as JPEG: the pane falls back by itself, and says why.
import { H264Stream, h264Support } from './video.js';
import { WhepStream, webrtcSupport } from './webrtc.js';

const NOT_LIVE_MS = 1500;  // WebRTC: no new picture this long is shown as not live

// A decoder that falls behind twice within this long cannot keep up at the pane's rate (a
// busy machine, many panes): the pane asks for fewer frames instead of starting over at a
// key frame again and again, each restart costing a key frame and a round trip (issue 29).
const BEHIND_WINDOW_MS = 10000;
const SLOWER = 0.6;           // each step down: 15 -> 9 -> 5 -> 3 Hz
const MIN_RATE_HZ = 3;
const STEP_UP_AFTER_MS = 30000;  // this long at a lower rate without falling behind: try higher

export class Pane {
  constructor(container, link, view, options = {}) {
    this.link = link;
    this.forceJpeg = !!options.forceJpeg;
    this.forceWebsocket = !!options.forceWebsocket;
    this.token = options.token || null;
    this.specOf = options.specOf || (() => null);
    // The revision this console's last update of the view returned (Steering): a frame of an
    // older one was on its way before the change took effect, and is not shown.
    this.minRevision = options.minRevision || (() => 0);
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
    this.videoEl = document.createElement('video');  // WebRTC's picture
    this.videoEl.muted = true;
    this.videoEl.playsInline = true;
    this.videoEl.autoplay = true;
    this.videoEl.hidden = true;
    this.el.append(this.canvas, this.videoEl, this.label, this.staleEl);
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
    this.encoding = null;     // 'H264' or 'JPEG': what the status line shows
    this.fallback = null;     // why JPEG when H.264 was not used
    this.video = null;        // H264Stream while on H.264
    this.picture = null;      // the last decoded VideoFrame (snapshots)
    this.rtc = null;          // WhepStream while on WebRTC
    this.rtcWhy = null;       // why not WebRTC
    this.rtcAgeMs = null;     // WebRTC: capture to display of the newest picture
    this.rtcStats = null;     // WebRTC: the browser's inbound-rtp stats (freezes, drops)
    this.stopped = false;
  }

  async start(rateHz) {
    this.rateHz = rateHz;
    this.fullRateHz = rateHz;
    this.behindTimes = [];   // when the decoder fell behind (resync), recent ones
    this.rateChangedAt = 0;
    if (this.forceJpeg || this.forceWebsocket) {
      this.rtcWhy = this.rtcWhy || 'the WebSocket asked for in the address';
    } else {
      const rtc = webrtcSupport();
      if (rtc.ok) {
        try {
          await this.startWebrtc();
          return;
        } catch (e) {
          console.warn('WebRTC of', this.view, 'not used:', e.message);
          this.rtcWhy = e.message;
        }
      } else {
        this.rtcWhy = rtc.reason;
      }
    }
    if (this.stopped) return;
    const support = this.forceJpeg ? { ok: false, reason: 'forced' } : await h264Support();
    if (!support.ok) return this.subscribe('JPEG', support.reason);
    try {
      await this.subscribe('H264');
    } catch (e) {
      console.warn('H.264 of', this.view, 'refused, JPEG instead:', e.message);
      await this.subscribe('JPEG', e.message);  // e.g. a view larger than H.264's largest picture
    }
  }

  async startWebrtc() {
    this.encoding = 'WebRTC';
    this.el.dataset.encoding = 'WebRTC';
    this.canvas.hidden = true;
    this.videoEl.hidden = false;
    this.rtc = new WhepStream(this.view, this.token, this.videoEl, (video, meta) => this.onVideoFrame(video, meta),
      (text) => this.showStale(text), (reason) => this.webrtcGaveUp(reason));
    try {
      await this.rtc.start();
    } catch (e) {
      this.rtc = null;
      this.encoding = null;
      this.canvas.hidden = false;
      this.videoEl.hidden = true;
      throw e;
    }
    this.liveTimer = setInterval(() => this.checkLive(), 500);
  }

  // A WebRTC picture shown: the pane's numbers and a header as the WebSocket's frames give
  // (the view's spec for gestures, the capture time for the status line's latency).
  onVideoFrame(video, meta) {
    this.frames++;
    const now = performance.now();
    this.fpsWindow.push(now);
    while (this.fpsWindow.length && this.fpsWindow[0] < now - 2000) this.fpsWindow.shift();
    this.rtcAgeMs = meta.captureMs === null ? null : meta.displayMs - meta.captureMs;
    this.header = {
      camera: { spec: this.specOf() }, sequence: this.frames, stale: false,
      captureTime: meta.captureMs === null ? null : new Date(meta.captureMs).toISOString(),
      width: video.videoWidth, height: video.videoHeight,
    };
    const w = this.el.clientWidth, h = this.el.clientHeight, iw = video.videoWidth, ih = video.videoHeight;
    const scale = Math.min(w / iw, h / ih);
    this.rect = { x: (w - iw * scale) / 2, y: (h - ih * scale) / 2, w: iw * scale, h: ih * scale, iw, ih };
    this.showStale(null);
  }

  checkLive() {
    if (!this.rtc) return;
    if (performance.now() - this.rtc.lastFrameAt > NOT_LIVE_MS && this.header) {
      this.header.stale = true;
      this.header.staleReason = 'no new pictures over WebRTC';
      if (this.staleEl.hidden) this.showStale(this.header.staleReason);
    }
    this.rtc.stats().then((s) => {
      if (!s) return;
      this.rtcStats = s;
      this.skipped = (s.framesDropped || 0);
    }).catch(() => {});
  }

  // The daemon refused a reconnection (the view gone, its limits): H.264 over the WebSocket.
  async webrtcGaveUp(reason) {
    if (!this.rtc || this.stopped) return;
    console.warn('WebRTC of', this.view, 'given up:', reason);
    this.rtc.stop();
    this.rtc = null;
    clearInterval(this.liveTimer);
    this.rtcWhy = reason;
    this.canvas.hidden = false;
    this.videoEl.hidden = true;
    this.forceWebsocket = true;
    await this.start(this.fullRateHz).catch((e) => this.showStale(e.message));
  }

  async subscribe(encoding, why, video = null) {
    this.encoding = encoding;
    this.fallback = why || null;
    this.el.dataset.encoding = encoding;
    const options = { max_rate_hz: this.rateHz, stale_frames: true };
    if (encoding === 'H264') {
      this.video = video || new H264Stream((frame) => this.onPicture(frame), (reason) => this.fallBack(reason),
        () => this.resync());
      options.encoding = 'H264';
    } else {
      options.quality = 80;
    }
    const channel = await this.link.subscribe(this.view, options, (header, bytes, error) => this.onFrame(header, bytes, error));
    // Stopped, or fallen back to JPEG, meanwhile: this one is not wanted any more.
    if (this.stopped || this.encoding !== encoding) this.link.unsubscribe(channel).catch(() => {});
    else this.channel = channel;
  }

  // The decoder needs a key frame: subscribe anew (a new subscriber starts at one). The old
  // subscription goes first (its frames are ignored from here on: the same access units
  // twice would break the picture); the decoder skips deltas until that key frame.
  async resync() {
    if (this.resyncing || this.stopped || this.encoding !== 'H264') return;
    this.resyncing = true;
    const now = performance.now();
    this.behindTimes = this.behindTimes.filter((t) => now - t < BEHIND_WINDOW_MS);
    this.behindTimes.push(now);
    if (this.behindTimes.length >= 2 && this.rateHz > MIN_RATE_HZ) {
      this.rateHz = Math.max(MIN_RATE_HZ, Math.round(this.rateHz * SLOWER));
      this.rateChangedAt = now;
      this.behindTimes = [];
      console.warn('H.264 of', this.view, 'decoded too slowly: asking for', this.rateHz, 'Hz');
    }
    const old = this.channel;
    this.channel = null;
    if (old !== null) this.link.unsubscribe(old).catch(() => {});
    try {
      await this.subscribe('H264', null, this.video);
    } catch (e) {
      console.warn('H.264 resync of', this.view, 'failed:', e.message);
    }
    this.resyncing = false;
  }

  // H.264 failed here: the same view as JPEG from now on.
  async fallBack(reason) {
    console.warn('H.264 of', this.view, 'given up, JPEG instead:', reason);
    const channel = this.channel;
    this.channel = null;
    if (this.video) this.video.close();
    this.video = null;
    if (channel !== null) await this.link.unsubscribe(channel).catch(() => {});
    if (!this.stopped) await this.subscribe('JPEG', reason).catch((e) => this.showStale(e.message));
  }

  async stop() {
    this.stopped = true;
    const channel = this.channel;
    this.channel = null;
    this.el.remove();
    if (this.rtc) this.rtc.stop();
    this.rtc = null;
    clearInterval(this.liveTimer);
    if (this.video) this.video.close();
    if (this.picture) this.picture.close();
    this.picture = null;
    if (channel !== null) await this.link.unsubscribe(channel).catch(() => {});
  }

  // Kept up at a lowered rate for a while: one step back up (resubscribing costs a key
  // frame, so at most once per STEP_UP_AFTER_MS).
  maybeStepUp() {
    if (this.rateHz >= this.fullRateHz || this.resyncing || this.encoding !== 'H264') return;
    const now = performance.now();
    if (now - this.rateChangedAt < STEP_UP_AFTER_MS || this.behindTimes.some((t) => now - t < STEP_UP_AFTER_MS)) return;
    this.rateHz = Math.min(this.fullRateHz, Math.round(this.rateHz / SLOWER));
    this.rateChangedAt = now;
    this.resync();
    this.behindTimes = [];  // that resync was ours, not the decoder's
  }

  // The encoding in use, for the status line: "WebRTC", "H264 (no WebRTC: why)", "H264 at
  // 9 Hz (decoder behind)", or "JPEG (why not H.264)".
  encodingLabel() {
    if (!this.encoding) return '…';
    if (this.encoding === 'WebRTC') return 'WebRTC';
    const short = (text) => (text.length > 48 ? text.slice(0, 47) + '…' : text);
    if (this.encoding === 'H264' && this.rtcWhy && this.rateHz >= this.fullRateHz) {
      return `H264 over WebSocket (no WebRTC: ${short(this.rtcWhy)})`;
    }
    if (this.encoding === 'H264' && this.rateHz < this.fullRateHz) return `H264 at ${this.rateHz} Hz (decoder behind)`;
    if (this.encoding !== 'JPEG' || !this.fallback) return this.encoding;
    // A short reason: the status line must fit a phone (the whole one is in the console log).
    const why = this.fallback.length > 48 ? this.fallback.slice(0, 47) + '…' : this.fallback;
    return `JPEG (${why})`;
  }

  onPicture(frame) {
    if (this.stopped) return frame.close();
    this.maybeStepUp();
    // A view of an odd side is coded one pixel larger (its edge repeated): the frame's
    // header says the view's own size.
    const h = this.header;
    this.draw(frame, Math.min(frame.displayWidth, (h && h.width) || frame.displayWidth),
      Math.min(frame.displayHeight, (h && h.height) || frame.displayHeight));
    if (this.picture) this.picture.close();
    this.picture = frame;
  }

  // The picture on screen as an image file: the JPEG/PNG as received, or the last decoded
  // video picture as PNG. Resolves with {blob, ext} or null.
  async snapshot() {
    if (this.encoding === 'WebRTC') {
      const v = this.videoEl;
      if (!v.videoWidth) return null;
      const canvas = document.createElement('canvas');
      canvas.width = v.videoWidth;
      canvas.height = v.videoHeight;
      canvas.getContext('2d').drawImage(v, 0, 0);
      const blob = await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
      return blob && { blob, ext: 'png' };
    }
    if (this.encoding !== 'H264') {
      if (!this.bytes) return null;
      const png = this.header.encoding === 'PNG';
      return { blob: new Blob([this.bytes], { type: png ? 'image/png' : 'image/jpeg' }), ext: png ? 'png' : 'jpg' };
    }
    if (!this.picture) return null;
    const canvas = document.createElement('canvas');
    canvas.width = Math.min(this.picture.displayWidth, (this.header && this.header.width) || Infinity);
    canvas.height = Math.min(this.picture.displayHeight, (this.header && this.header.height) || Infinity);
    canvas.getContext('2d').drawImage(this.picture, 0, 0);
    const blob = await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
    return blob && { blob, ext: 'png' };
  }

  onFrame(header, bytes, error) {
    if (!header) {
      this.showStale('stream ended: ' + (error ? error.message : ''));
      return;
    }
    // H.264 is decoded whole (each access unit refers to the last); the daemon sends no
    // frame of an older view once the update returned (docs/API.md, "Streams").
    const revision = Number((header.camera && header.camera.revision) || 0);
    if (header.encoding !== 'H264' && revision < this.minRevision()) return;
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
    if (header.encoding === 'H264') {
      // Every access unit goes to the decoder, in order: each is coded against the last.
      if (this.video) this.video.push(bytes);
      return;
    }
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
        this.draw(bitmap, bitmap.width, bitmap.height);
        bitmap.close();
      } catch (e) {
        console.warn('frame of', this.view, 'not decoded:', e);
      }
    }
    this.decoding = false;
  }

  draw(image, iw, ih) {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.el.clientWidth * dpr));
    const h = Math.max(1, Math.round(this.el.clientHeight * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    const scale = Math.min(w / iw, h / ih);
    const dw = iw * scale;
    const dh = ih * scale;
    const x = (w - dw) / 2;
    const y = (h - dh) / 2;
    const ctx = this.canvas.getContext('2d');
    ctx.fillStyle = '#000';
    ctx.fillRect(0, 0, w, h);
    ctx.drawImage(image, 0, 0, iw, ih, x, y, dw, dh);
    this.rect = { x: x / dpr, y: y / dpr, w: dw / dpr, h: dh / dpr, iw, ih };
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
    if (this.encoding === 'WebRTC') return this.rtcAgeMs;
    if (!this.header || !this.header.captureTime) return null;
    return Date.now() - Date.parse(this.header.captureTime);
  }
}
