// The method's own operator layout (Oehler & von Stryk, ECMR 2021): the coloured lidar
// cloud in a 3D panel above (three.js from Debian's libjs-three, served by the daemon under
// /javascript/), a forward and a backward virtual camera below.
const BACK_VIEW = 'console_back';

export async function startPaper(app, addPane, toast, forwardName) {
  const forward = app.views.find((v) => v.spec.name === forwardName).spec;
  const cloud = new CloudPanel(app.link, document.getElementById('panes'), toast);
  await cloud.start();
  addPane(forward.name);
  const back = await backwardView(app, forward, toast);
  if (back.view) addPane(back.view);
  else missingPane(`No backward camera: ${back.why}`);
  return cloud;
}

// The backward pane's place when there is no backward view: says why, rather than grey.
function missingPane(text) {
  const el = document.createElement('div');
  el.className = 'pane missing';
  const message = document.createElement('p');
  message.textContent = text;
  el.append(message);
  document.getElementById('panes').append(el);
}

// A view named back/rear if the daemon has one; else the forward view turned round,
// created once (operators only). {view}, or {why} there is none.
async function backwardView(app, forward, toast) {
  const known = app.views.find((v) => ['back', 'rear', BACK_VIEW].includes(v.spec.name));
  if (known) return { view: known.spec.name };
  if (app.link.role === 'viewer') {
    return { why: `the robot has no view named "back", and only an operator's console can create one (${BACK_VIEW}).` };
  }
  const spec = { ...forward, name: BACK_VIEW, yawDeg: (forward.yawDeg || 0) + 180 };
  try {
    const view = await app.link.call('CreateView', { spec });
    app.views.push(view);
    app.initial.set(BACK_VIEW, view.spec);
  } catch (e) {
    if (e.code !== 'ALREADY_EXISTS') {
      toast(`backward camera: ${e.message}`);
      return { why: e.message };
    }
  }
  return { view: BACK_VIEW };
}

class CloudPanel {
  constructor(link, container, toast) {
    this.link = link;
    this.toast = toast;
    this.el = document.createElement('div');
    this.el.className = 'pane cloud';
    this.label = document.createElement('div');
    this.label.className = 'label';
    this.label.textContent = 'cloud';
    this.el.append(this.label);
    container.append(this.el);
    this.channel = null;
    this.stopped = false;
    this.points = 0;
  }

  async start() {
    let THREE, OrbitControls;
    try {
      THREE = await import('/javascript/three/build/three.module.js');
      ({ OrbitControls } = await import('/javascript/three/examples/jsm/controls/OrbitControls.js'));
    } catch (e) {
      this.label.textContent = 'cloud: the 3D panel needs Debian\'s libjs-three on the robot (apt-get install libjs-three)';
      return;
    }
    this.THREE = THREE;
    try {
      this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      this.label.textContent = 'cloud: this browser offers no WebGL';
      return;
    }
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.el.prepend(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(60, 1, 0.05, 200);
    this.camera.up.set(0, 0, 1);  // REP-103: z up
    this.camera.position.set(-6, 0, 4);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.set(1, 0, 0);
    this.controls.update();
    this.scene.add(new THREE.AxesHelper(0.5));
    this.geometry = new THREE.BufferGeometry();
    this.cloud = new THREE.Points(this.geometry, new THREE.PointsMaterial({ size: 0.04, vertexColors: true }));
    this.scene.add(this.cloud);
    const loop = () => {
      if (this.stopped) return;
      this.resize();
      this.renderer.render(this.scene, this.camera);
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
    try {
      const r = await this.link.call(null, null,
        { op: 'subscribe_cloud', request: { maxRateHz: 5, options: { voxelSizeM: 0.05 } } });
      this.channel = r.channel;
      this.link.channels.set(r.channel, (header, bytes, error) => this.onCloud(header, bytes, error));
    } catch (e) {
      this.label.textContent = `cloud: ${e.message}`;
    }
  }

  resize() {
    const w = this.el.clientWidth;
    const h = this.el.clientHeight;
    if (w && h && (w !== this.w || h !== this.h)) {
      this.w = w;
      this.h = h;
      this.renderer.setSize(w, h);
      this.camera.aspect = w / h;
      this.camera.updateProjectionMatrix();
    }
  }

  // Packed points (docs/API.md, "Point clouds"): fields looked up by name.
  onCloud(header, bytes, error) {
    if (!header) {
      this.label.textContent = `cloud: ${error ? error.message : 'ended'}`;
      return;
    }
    const offset = {};
    for (const f of header.fields || []) offset[f.name] = f.offset || 0;
    const stride = header.pointStride;
    const n = Number(header.pointCount || 0);
    const data = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const positions = new Float32Array(n * 3);
    const colours = new Float32Array(n * 3);
    for (let i = 0; i < n; i++) {
      const at = i * stride;
      positions[3 * i] = data.getFloat32(at + offset.x, true);
      positions[3 * i + 1] = data.getFloat32(at + offset.y, true);
      positions[3 * i + 2] = data.getFloat32(at + offset.z, true);
      const coloured = 'flags' in offset ? (data.getUint8(at + offset.flags) & 1) : 1;
      for (let c = 0; c < 3; c++) {
        colours[3 * i + c] = coloured ? data.getUint8(at + offset['rgb'[c]]) / 255 : 0.35;
      }
    }
    this.geometry.setAttribute('position', new this.THREE.BufferAttribute(positions, 3));
    this.geometry.setAttribute('color', new this.THREE.BufferAttribute(colours, 3));
    this.geometry.computeBoundingSphere();
    this.points = n;
    this.label.textContent = `cloud: ${n} points (${header.frame})`;
  }

  stop() {
    this.stopped = true;
    if (this.channel !== null) this.link.unsubscribe(this.channel).catch(() => {});
    if (this.renderer) this.renderer.dispose();
    this.el.remove();
  }
}
