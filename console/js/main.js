// The operator console: connects, lists the views, lays out panes, steers, shows status.
import { ApiError, Link } from './link.js';
import { Pane } from './pane.js';
import { Steering } from './steering.js';
import { attachGestures } from './gestures.js';
import { Gamepads } from './gamepad.js';
import { lookAt } from './look.js';

const RATE_HZ = 15;
const ZOOMABLE = new Set(['PERSPECTIVE', 'BIRDSEYE', 'FISHEYE']);

const $ = (id) => document.getElementById(id);

const app = {
  link: null,
  views: [],                 // View messages (ListViews)
  initial: new Map(),        // view name -> spec as first seen (double tap goes back to it)
  steering: new Map(),       // view name -> Steering
  panes: [],
  layout: 'single',
  cloud: null,
  status: null,
  // ?encoding=jpeg: JPEG even where the browser decodes H.264 (e.g. to compare, or a
  // browser whose H.264 decoding misbehaves).
  forceJpeg: new URLSearchParams(location.search).get('encoding') === 'jpeg',
  // ?transport=websocket: the WebSocket even where WebRTC works (to compare the two).
  forceWebsocket: new URLSearchParams(location.search).get('transport') === 'websocket',
};
window.omniviewConsole = app;  // for people (the devtools) and the browser tests

function toast(text) {
  const t = $('toast');
  t.textContent = text;
  t.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => { t.hidden = true; }, 4000);
}

function spec(name) {
  const v = app.views.find((x) => x.spec.name === name);
  return v ? v.spec : null;
}

function steeringFor(view) {
  if (!app.steering.has(view)) {
    app.steering.set(view, new Steering(app.link, view, (e) => toast(`${view}: ${e.code}: ${e.message}`)));
  }
  return app.steering.get(view);
}

// The one view that the gamepad (sticks and A), tap-to-look and a double tap on the
// bird's-eye steer: the first view on screen that is not a bird's-eye (in Split: front), so
// what turns is in sight; else a view named "ptz"; else the first perspective view.
function steerTarget() {
  const shown = app.panes.map((p) => p.view).find((n) => spec(n) && spec(n).type !== 'BIRDSEYE');
  if (shown) return shown;
  if (spec('ptz')) return 'ptz';
  const any = app.views.find((v) => v.spec.type === 'PERSPECTIVE');
  return any ? any.spec.name : null;
}

function recentre(target) {
  const first = target && app.initial.get(target);
  if (first) steeringFor(target).set({ yawDeg: first.yawDeg, pitchDeg: first.pitchDeg, hfovDeg: first.hfovDeg });
}

// The view of that name if there is one, else the first of that type, else the first.
function pickView(type, name) {
  if (spec(name)) return name;
  return (app.views.find((v) => v.spec.type === type) || app.views[0] || { spec: {} }).spec.name;
}

function addPane(view) {
  const s = spec(view);
  const birdseye = s && s.type === 'BIRDSEYE';
  // No steering hints for a viewer: its token cannot steer.
  const hint = app.link.role === 'viewer' ? null
    : birdseye ? 'tap: look there' : 'drag: pan/tilt · pinch/wheel: zoom · double tap: centre';
  const pane = new Pane($('panes'), app.link, view,
    { forceJpeg: app.forceJpeg, forceWebsocket: app.forceWebsocket, token: sessionStorage.getItem('omniview-token'),
      specOf: () => spec(view), hint, minRevision: () => (app.steering.has(view) ? app.steering.get(view).revision : 0) });
  attachGestures(pane.el, {
    drag: (dx, dy) => {
      if (birdseye) return;
      const k = pane.degreesPerPixel();
      steeringFor(view).add(dx * k, -dy * k);  // the picture follows the finger
    },
    zoom: (factor) => { if (s && ZOOMABLE.has(s.type)) steeringFor(view).add(0, 0, factor); },
    recentre: () => recentre(birdseye ? steerTarget() : view),
    tap: (x, y) => {
      if (!birdseye) return;
      const target = steerTarget();
      const pixel = pane.toImage(x, y);
      if (!target || !pixel) return;
      lookAt(app.link, view, pixel, target).then(
        (set) => steeringFor(target).set(set),
        (e) => toast(e.message));
    },
  });
  app.panes.push(pane);
  pane.start(RATE_HZ).catch((e) => { pane.showStale(e.message); toast(`${view}: ${e.message}`); });
  return pane;
}

async function setLayout(layout, view) {
  for (const p of app.panes) p.stop();
  app.panes = [];
  if (app.cloud) { app.cloud.stop(); app.cloud = null; }
  $('panes').replaceChildren();  // and any placeholder (Paper's missing backward camera)
  app.layout = layout;
  $('panes').className = layout;
  for (const b of document.querySelectorAll('#layouts button')) b.classList.toggle('active', b.dataset.layout === layout);
  if (layout === 'split') {
    addPane(pickView('BIRDSEYE', 'birdseye'));
    addPane(pickView('PERSPECTIVE', 'front'));
  } else if (layout === 'paper') {
    const { startPaper } = await import('./paper.js');
    app.cloud = await startPaper(app, addPane, toast, pickView('PERSPECTIVE', 'front'));
  } else {
    addPane(view || $('view-select').value || pickView('PERSPECTIVE', 'front'));
  }
  // The dropdown names the main (first) pane's view, whatever the layout.
  if (app.panes[0] && spec(app.panes[0].view)) $('view-select').value = app.panes[0].view;
  showDepth();
  const url = new URL(location.href);
  url.searchParams.set('layout', layout);
  if (layout === 'single') url.searchParams.set('view', app.panes[0] ? app.panes[0].view : '');
  else url.searchParams.delete('view');
  history.replaceState(null, '', url.pathname + url.search);
}

async function loadViews() {
  const r = await app.link.call('ListViews', {});
  app.views = r.views || [];
  for (const v of app.views) if (!app.initial.has(v.spec.name)) app.initial.set(v.spec.name, v.spec);
  const select = $('view-select');
  const chosen = select.value;
  select.replaceChildren(...app.views.map((v) => new Option(`${v.spec.name} (${v.spec.type.toLowerCase()})`, v.spec.name)));
  if (chosen && spec(chosen)) select.value = chosen;
}

// The depth button names the first pane's surface (operators switch it; viewers only see it).
function showDepth() {
  const s = app.panes[0] && spec(app.panes[0].view);
  const button = $('depth');
  button.textContent = `Depth: ${s && s.depth === 'MEASURED' ? 'measured' : 'fixed'}`;
  button.disabled = !s || app.link.role === 'viewer';
}

async function toggleDepth() {
  const view = app.panes[0] && app.panes[0].view;
  const s = view && spec(view);
  if (!s) return;
  try {
    await app.link.call('UpdateView', { name: view, set: { depth: s.depth === 'MEASURED' ? 'FIXED' : 'MEASURED' } });
    await loadViews();
    showDepth();
  } catch (e) {
    toast(`${view}: ${e.code}: ${e.message}`);
  }
}

// A span of the status line; `unit` ones never break inside (a figure and its unit).
function statusSpan(className, ...children) {
  const span = document.createElement('span');
  span.className = className;
  span.append(...children);
  return span;
}

function showStatus(st) {
  app.status = st;
  const el = $('status');
  const src = (st.sources || [])[0];
  const parts = [];
  // Text nodes only: view and source names come from the daemon (any operator can name a view).
  // One segment for the source and one per pane: on a phone the line wraps between them,
  // and inside one only between figures, so none is cut off.
  if (src) {
    el.dataset.connected = String(!!src.connected);
    el.dataset.sourceRate = String(src.rateHz || 0);
    const dot = statusSpan('dot' + (src.connected ? ' on' : ''));
    parts.push(statusSpan('segment', dot, `${src.name} `, statusSpan('unit', `${(src.rateHz || 0).toFixed(1)} Hz`)));
  }
  for (const p of app.panes) {
    const age = p.ageMs();
    const segment = statusSpan('segment', `${p.view} ${p.encodingLabel()} `,
      statusSpan('unit', `${p.fps().toFixed(1)} fps`), ' · ',
      statusSpan('unit', age === null ? '–' : Math.round(age) + ' ms'), ' · ',
      statusSpan('unit', `dropped ${p.skipped}`));
    // A measured-depth view: how much of it stands on the lidar (none yet: why).
    const vs = (st.views || []).find((v) => v.name === p.view);
    if (vs && (spec(p.view) || {}).depth === 'MEASURED') {
      segment.append(' · ', statusSpan('unit', vs.depthMessage && !vs.measuredDepth
        ? 'depth: ' + vs.depthMessage : `depth ${Math.round(100 * (vs.measuredDepth || 0))}% measured`));
    }
    parts.push(segment);
  }
  el.replaceChildren(...parts);
  const down = (st.sources || []).filter((s) => !s.connected);
  const degraded = (st.sources || []).filter((s) => s.connected && s.degraded);
  const stale = app.panes.find((p) => p.header && p.header.stale);
  const banner = $('banner');
  if (down.length) {
    banner.textContent = `Robot disconnected: ${down.map((s) => `${s.name}: ${s.message || 'not connected'}`).join('; ')}`;
  } else if (stale) {
    banner.textContent = `Not live: ${stale.header.staleReason || 'no new images'}`;
  } else if (degraded.length) {
    banner.textContent = `Robot link degraded: ${degraded.map((s) =>
      `${s.name}: ${Math.round(100 * (s.failureRate || 0))}% of requests fail${s.message ? ' (' + s.message + ')' : ''}`).join('; ')}`;
  }
  banner.hidden = !(down.length || stale || degraded.length);
}

async function pollStatus() {
  try {
    showStatus(await app.link.call('GetStatus', {}));
  } catch (e) {
    if (e.code !== 'UNAVAILABLE') toast(e.message);
  }
}

async function snapshot() {
  const pane = app.panes.find((p) => p.header);
  const shot = pane && await pane.snapshot();
  if (!shot) return toast('no frame yet');
  const a = document.createElement('a');
  a.href = URL.createObjectURL(shot.blob);
  a.download = `${pane.view}-${pane.header.sequence}.${shot.ext}`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// The token: from the address's fragment (#token=..., never sent to the server, removed
// from the address bar at once), else this tab's earlier one, else the login form.
function takeToken() {
  // Not URLSearchParams: it reads '+' as a space, and base64 tokens hold '+'.
  const match = location.hash.match(/(?:^#|&)token=([^&]*)/);
  if (match) {
    sessionStorage.setItem('omniview-token', decodeURIComponent(match[1]));
    history.replaceState(null, '', location.pathname + location.search);
  }
  return sessionStorage.getItem('omniview-token');
}

async function connect() {
  const url = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws';
  app.link = new Link(url);
  app.link.addEventListener('close', (e) => {
    $('status').textContent = `disconnected: ${e.detail.reason || 'code ' + e.detail.code}`;
    $('status').dataset.connected = 'false';
  });
  app.link.addEventListener('error', (e) => toast(`${e.detail.code}: ${e.detail.message}`));
  try {
    await app.link.open(takeToken());
  } catch (e) {
    if (e instanceof ApiError && (e.code === 'UNAUTHENTICATED' || e.code === 'UNAVAILABLE')) {
      sessionStorage.removeItem('omniview-token');
      $('login').hidden = false;
      $('login-error').textContent = e.code === 'UNAUTHENTICATED' && !takeToken() ? '' : e.message;
      $('status').textContent = 'not connected: ' + e.message;
      return false;
    }
    throw e;
  }
  $('login').hidden = true;
  $('role').textContent = app.link.role === 'viewer' ? 'viewer: watching only' : app.link.role;
  return true;
}

async function main() {
  $('login').addEventListener('submit', (e) => {
    e.preventDefault();
    sessionStorage.setItem('omniview-token', $('token').value.trim());
    location.reload();
  });
  if (!(await connect())) return;
  await loadViews();
  const params = new URLSearchParams(location.search);
  const view = params.get('view');
  // Single's view: the address's, else front (not whichever view the list has first).
  $('view-select').value = view && spec(view) ? view : pickView('PERSPECTIVE', 'front');
  $('view-select').addEventListener('change', () => setLayout('single', $('view-select').value));
  for (const b of document.querySelectorAll('#layouts button')) b.addEventListener('click', () => setLayout(b.dataset.layout));
  $('snapshot').addEventListener('click', snapshot);
  $('depth').addEventListener('click', toggleDepth);
  await setLayout(params.get('layout') || 'single', view && spec(view) ? view : undefined);
  pollStatus();
  setInterval(pollStatus, 1000);
  // A page that goes ends its WebRTC sessions at once (their DELETE is sent as the page unloads).
  window.addEventListener('pagehide', () => { for (const p of app.panes) p.stop(); });
  // Sticks and A act on the same view.
  new Gamepads((yaw, pitch, zoom) => {
    const target = steerTarget();
    if (target) steeringFor(target).add(yaw, pitch, ZOOMABLE.has((spec(target) || {}).type) ? zoom : 1);
  }, () => recentre(steerTarget())).start();
}

main().catch((e) => {
  console.error(e);
  $('status').textContent = 'error: ' + e.message;
});
