// Steers one view through the API's UpdateView, as a gRPC joystick client does: gestures
// add up pan/tilt/zoom steps here, and at most one update is in flight and at most 30 are
// sent a second, so a fast drag never queues work on the daemon.

const MIN_INTERVAL_MS = 1000 / 30;

export class Steering {
  constructor(link, view, onError) {
    this.link = link;
    this.view = view;
    this.onError = onError;
    this.delta = { yaw: 0, pitch: 0, zoom: 1 };
    this.absolute = null;   // a ViewSpec to set (re-centre, tap-to-look); replaces pending steps
    this.inFlight = false;
    this.last = 0;
    this.timer = null;
    this.updates = 0;       // sent, for the status line and tests
    this.revision = 0;      // the newest revision an update returned: older frames are not shown
  }

  add(yawDeg, pitchDeg, zoom = 1) {
    this.delta.yaw += yawDeg;
    this.delta.pitch += pitchDeg;
    this.delta.zoom *= zoom;
    this.schedule();
  }

  set(spec) {
    this.absolute = spec;
    this.delta = { yaw: 0, pitch: 0, zoom: 1 };
    this.schedule();
  }

  pending() {
    return this.absolute !== null || this.delta.yaw !== 0 || this.delta.pitch !== 0 || this.delta.zoom !== 1;
  }

  schedule() {
    if (this.inFlight || this.timer || !this.pending()) return;
    const wait = Math.max(0, this.last + MIN_INTERVAL_MS - performance.now());
    this.timer = setTimeout(() => { this.timer = null; this.send(); }, wait);
  }

  async send() {
    if (this.inFlight || !this.pending()) return;
    const request = { name: this.view };
    if (this.absolute) {
      request.set = this.absolute;
    } else {
      request.delta = { yawDeg: this.delta.yaw, pitchDeg: this.delta.pitch, zoom: this.delta.zoom };
    }
    this.absolute = null;
    this.delta = { yaw: 0, pitch: 0, zoom: 1 };
    this.inFlight = true;
    this.last = performance.now();
    try {
      const view = await this.link.call('UpdateView', request);
      this.revision = Math.max(this.revision, Number((view && view.revision) || 0));
      this.updates++;
    } catch (e) {
      this.onError(e);
    } finally {
      this.inFlight = false;
      this.schedule();
    }
  }
}
