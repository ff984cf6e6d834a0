// Gamepad steering (the browser's Gamepad API), as the paper's operators steer the virtual
// camera with a joystick: left stick pans and tilts at a rate, the triggers zoom, A
// re-centres. Polled once per animation frame; the steps go through the same Steering (so
// still at most 30 UpdateView calls a second).
const DEAD_ZONE = 0.15;
const PAN_DEG_S = 90;
const TILT_DEG_S = 60;
const ZOOM_PER_S = 2;

export class Gamepads {
  constructor(onStep, onRecentre) {
    this.onStep = onStep;
    this.onRecentre = onRecentre;
    this.last = null;
    this.wasPressed = false;
  }

  start() {
    const tick = (now) => {
      this.poll(now);
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }

  poll(now) {
    const dt = this.last === null ? 0 : Math.min(0.1, (now - this.last) / 1000);
    this.last = now;
    const pad = [...(navigator.getGamepads ? navigator.getGamepads() : [])].find((g) => g && g.connected);
    if (!pad || dt === 0) return;
    const axis = (i) => (Math.abs(pad.axes[i] || 0) < DEAD_ZONE ? 0 : pad.axes[i]);
    const button = (i) => (pad.buttons[i] ? pad.buttons[i].value : 0);
    const yaw = -axis(0) * PAN_DEG_S * dt;      // stick right turns right (yaw is left-positive)
    const pitch = axis(1) * TILT_DEG_S * dt;    // stick pulled back looks down
    const zoom = Math.pow(ZOOM_PER_S, (button(7) - button(6)) * dt);
    if (yaw || pitch || zoom !== 1) this.onStep(yaw, pitch, zoom);
    const pressed = button(0) > 0.5;
    if (pressed && !this.wasPressed) this.onRecentre();
    this.wasPressed = pressed;
  }
}
