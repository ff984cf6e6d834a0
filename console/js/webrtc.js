// A view over WebRTC (WHEP, docs/API.md "WebRTC"): the browser's own RTCPeerConnection
// receives the view's H.264 as RTP over UDP (NACK retransmission, late frames dropped, not
// waited for), so a lossy Wi-Fi costs a glitch instead of the freeze TCP gives.
//
// Signalling is WHEP: one POST of the offer (with every ICE candidate: no trickle) answered
// by the daemon's SDP, one DELETE at the end. A link that drops (no picture for a while, or
// ICE failed) is started again with a new offer, so the picture resumes by itself.

const GATHER_MS = 2000;       // ICE candidates gathered before the offer goes out
const FIRST_FRAME_MS = 8000;  // no picture this long after the POST: WebRTC does not work here
const RESTART_AFTER_MS = 4000;  // no picture this long once playing: the link dropped, start again

// Whether this browser can do WebRTC at all ({ok, reason}).
export function webrtcSupport() {
  if (typeof RTCPeerConnection === 'undefined') return { ok: false, reason: 'no WebRTC in this browser' };
  if (!('requestVideoFrameCallback' in HTMLVideoElement.prototype)) {
    return { ok: false, reason: 'no requestVideoFrameCallback in this browser' };
  }
  return { ok: true };
}

// The RTP clock's tie to capture time, from the answer's Omniview-Capture-Clock header:
// capture (Unix ms) = unix_us / 1000 + (rtp - offset mod 2^32) / 90.
function captureClock(header) {
  const m = /rtp=(\d+); *unix_us=(\d+)/.exec(header || '');
  return m ? { offset: Number(m[1]), epochMs: Number(m[2]) / 1000 } : null;
}

export class WhepStream {
  // onFrame(video, {captureMs, displayMs}) for each picture shown; onStatus(text) while
  // (re)connecting; onGiveUp(reason) where WebRTC cannot work (the pane falls back).
  constructor(view, token, video, onFrame, onStatus, onGiveUp) {
    this.view = view;
    this.token = token;
    this.video = video;
    this.onFrame = onFrame;
    this.onStatus = onStatus;
    this.onGiveUp = onGiveUp;
    this.pc = null;
    this.location = null;
    this.clock = null;
    this.lastFrameAt = 0;
    this.everPlayed = false;
    this.stopped = false;
    this.restarts = 0;
    this.watchdog = null;
  }

  // Resolves once the first picture is shown; rejects (with the reason) where this link or
  // daemon cannot do WebRTC: the caller falls back to WebSocket.
  async start() {
    await this.connect();
    const started = performance.now();
    while (!this.everPlayed) {
      if (this.stopped) throw new Error('stopped');
      if (performance.now() - started > FIRST_FRAME_MS) {
        const state = this.pc ? this.pc.iceConnectionState : 'none';
        this.stop();
        throw new Error(`no picture within ${FIRST_FRAME_MS / 1000} s (ICE ${state}: is UDP blocked?)`);
      }
      await new Promise((r) => setTimeout(r, 100));
    }
    this.watchdog = setInterval(() => this.watch(), 500);
  }

  async connect() {
    const pc = new RTCPeerConnection({ bundlePolicy: 'max-bundle' });
    this.pc = pc;
    pc.addTransceiver('video', { direction: 'recvonly' });
    pc.ontrack = (event) => {
      this.video.srcObject = new MediaStream([event.track]);
      this.video.play().catch(() => {});
    };
    await pc.setLocalDescription(await pc.createOffer());
    await new Promise((resolve) => {
      if (pc.iceGatheringState === 'complete') return resolve();
      const timer = setTimeout(resolve, GATHER_MS);
      pc.addEventListener('icegatheringstatechange', () => {
        if (pc.iceGatheringState === 'complete') { clearTimeout(timer); resolve(); }
      });
    });
    const headers = { 'Content-Type': 'application/sdp' };
    if (this.token) headers.Authorization = 'Bearer ' + this.token;
    const r = await fetch('/whep/' + encodeURIComponent(this.view), { method: 'POST', headers, body: pc.localDescription.sdp });
    const text = await r.text();
    if (r.status !== 201) {
      pc.close();
      throw new Error(`WHEP ${r.status}: ${text.trim()}`);
    }
    this.location = r.headers.get('Location');
    this.clock = captureClock(r.headers.get('Omniview-Capture-Clock'));
    await pc.setRemoteDescription({ type: 'answer', sdp: text });
    // One chain of frame callbacks per <video>: a pending callback outlives the stream it
    // was asked on, so a chain armed at every reconnect counted each picture once more per
    // reconnect (the status line read 30 fps on a 15 Hz view after one link drop).
    if (this.frameCallback !== undefined) this.video.cancelVideoFrameCallback(this.frameCallback);
    this.requestFrame();
  }

  requestFrame() {
    const video = this.video;
    this.frameCallback = video.requestVideoFrameCallback((now, meta) => {
      if (this.stopped) return;
      this.lastFrameAt = performance.now();
      this.everPlayed = true;
      const displayMs = performance.timeOrigin + (meta.expectedDisplayTime || now);
      let captureMs = null;
      if (this.clock && meta.rtpTimestamp !== undefined) {
        // The 32-bit RTP clock wraps every 13.3 h: the capture time nearest to now.
        const wrapMs = 4294967296 / 90;
        captureMs = this.clock.epochMs + (((meta.rtpTimestamp - this.clock.offset) >>> 0) / 90);
        captureMs += Math.round((displayMs - captureMs) / wrapMs) * wrapMs;
      }
      this.onFrame(video, { captureMs, displayMs });
      this.requestFrame();
    });
  }

  // Once playing: a link that stopped delivering is started again (a new offer).
  async watch() {
    if (this.stopped || this.restarting) return;
    const silentMs = performance.now() - this.lastFrameAt;
    const state = this.pc ? this.pc.iceConnectionState : 'closed';
    if (silentMs < RESTART_AFTER_MS && state !== 'failed' && state !== 'closed') return;
    this.restarting = true;
    this.onStatus(`no picture for ${(silentMs / 1000).toFixed(0)} s (ICE ${state}): reconnecting`);
    this.end();
    try {
      await this.connect();
      this.restarts++;
    } catch (e) {
      // The daemon refused (view gone, limits): the pane decides; a network error: try again.
      if (/^WHEP (4|503)/.test(e.message)) this.onGiveUp(e.message);
    }
    this.lastFrameAt = performance.now();  // give the new connection its time
    this.restarting = false;
  }

  // Frames the browser dropped and froze for (RTCInboundRtpStreamStats), for the status line.
  async stats() {
    if (!this.pc) return null;
    for (const s of (await this.pc.getStats()).values()) {
      if (s.type === 'inbound-rtp' && s.kind === 'video') return s;
    }
    return null;
  }

  end() {
    if (this.location) {
      const headers = this.token ? { Authorization: 'Bearer ' + this.token } : {};
      fetch(this.location, { method: 'DELETE', headers, keepalive: true }).catch(() => {});
      this.location = null;
    }
    if (this.pc) this.pc.close();
    this.pc = null;
  }

  stop() {
    this.stopped = true;
    clearInterval(this.watchdog);
    this.end();
    this.video.srcObject = null;
  }
}
