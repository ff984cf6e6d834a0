// Mouse and touch on a pane, turned into steering: drag pans and tilts (the picture follows
// the finger), pinch or wheel zooms, double tap or double click re-centres, a single tap
// (no movement) is reported for tap-to-look.

const TAP_SLOP_PX = 8;
const DOUBLE_TAP_MS = 300;

export function attachGestures(element, handlers) {
  const pointers = new Map();  // id -> {x, y, startX, startY}
  let pinchDistance = null;
  let lastTap = 0;
  let moved = false;

  const distance = () => {
    const [a, b] = [...pointers.values()];
    return Math.hypot(a.x - b.x, a.y - b.y);
  };

  element.addEventListener('pointerdown', (e) => {
    try {
      element.setPointerCapture(e.pointerId);  // keep the drag when the finger leaves the pane
    } catch (err) {
      // not an active pointer (a synthesised event): the drag still works inside the pane
    }
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY });
    if (pointers.size === 1) moved = false;
    if (pointers.size === 2) pinchDistance = distance();
  });

  element.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const dx = e.clientX - p.x;
    const dy = e.clientY - p.y;
    p.x = e.clientX;
    p.y = e.clientY;
    if (Math.hypot(p.x - p.startX, p.y - p.startY) > TAP_SLOP_PX) moved = true;
    if (pointers.size === 2) {
      const d = distance();
      if (pinchDistance > 0 && d > 0) handlers.zoom(d / pinchDistance);
      pinchDistance = d;
    } else if (pointers.size === 1 && moved) {
      handlers.drag(dx, dy);
    }
  });

  const end = (e) => {
    if (!pointers.has(e.pointerId)) return;
    const p = pointers.get(e.pointerId);
    pointers.delete(e.pointerId);
    if (pointers.size < 2) pinchDistance = null;
    if (e.type !== 'pointerup' || moved || pointers.size > 0) return;
    const now = performance.now();
    if (now - lastTap < DOUBLE_TAP_MS) {
      lastTap = 0;
      handlers.recentre();
    } else {
      lastTap = now;
      const rect = element.getBoundingClientRect();
      handlers.tap(p.x - rect.left, p.y - rect.top);
    }
  };
  element.addEventListener('pointerup', end);
  element.addEventListener('pointercancel', end);

  element.addEventListener('wheel', (e) => {
    e.preventDefault();
    handlers.zoom(Math.exp(-e.deltaY * 0.0015));
  }, { passive: false });
}
