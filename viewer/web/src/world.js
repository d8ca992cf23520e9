// The 3D view: every body of a recording header (docs/recording.md) as three.js meshes, posed per frame from
// the pose channels; the floor; contacts; joint axes; camera presets; the Camera Manager's extra views (a camera
// fixed to a body such as the head, one following a robot, a preset) side by side with the main one; picking.
// Entirely data-driven: any number of robots and objects. World frame +Y up, +Z forward, metres, quaternions
// [w, x, y, z].
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const CONTACT_CAPACITY = 512;
const UP = new THREE.Vector3(0, 1, 0);
// Camera offsets from the robot's centre, in robot sizes: the presets of the original (follow: front-right).
const PRESET_OFFSETS = {
  front: [0, 0.45, 1], back: [0, 0.45, -1], left: [1, 0.45, 0], right: [-1, 0.45, 0],
  top: [0, 1.3, 0.001], follow: [-0.62, 0.38, 0.78],
};
// A three.js camera looks along its -Z; a body's forward is its +Z: half a turn about +Y between them.
const LOOK_FORWARD = new THREE.Quaternion().setFromAxisAngle(UP, Math.PI);
const MAX_VIEWS = 3;  // extra views beside the main one: each gets a column of the canvas

function colorOf(rgba) {
  const c = Array.isArray(rgba) && rgba.length >= 3 ? rgba : [180, 180, 180, 255];
  return {
    color: new THREE.Color().setRGB(c[0] / 255, c[1] / 255, c[2] / 255, THREE.SRGBColorSpace),
    opacity: c.length >= 4 ? c[3] / 255 : 1,
  };
}

// The original's built-in textures as simple grey patterns (64 × 64 px, drawn once each), multiplied by the geom's
// colour as three.js does with a material's map: "Dynamixel" (a servo's ribbed case with its four horn screws),
// "Alu" (brushed metal), "AccelBoard" (a circuit board with its chip); any other name a checker, so that a
// textured object still looks textured (docs/viewer.md, "Textures").
const TEXTURE_PAINTERS = {
  Dynamixel(g) {
    g.fillStyle = '#b8b8b8';
    g.fillRect(0, 0, 64, 64);
    g.fillStyle = '#7a7a7a';
    for (let x = 4; x < 64; x += 8) g.fillRect(x, 0, 3, 64);
    g.fillStyle = '#ffffff';
    for (const [x, y] of [[16, 16], [48, 16], [16, 48], [48, 48]]) {
      g.beginPath();
      g.arc(x, y, 4, 0, 2 * Math.PI);
      g.fill();
    }
  },
  Alu(g) {
    for (let y = 0; y < 64; y++) {
      const v = 200 + ((y * 37) % 11) * 5;  // fixed streaks: the same picture every time
      g.fillStyle = `rgb(${v},${v},${v})`;
      g.fillRect(0, y, 64, 1);
    }
  },
  AccelBoard(g) {
    g.fillStyle = '#d0d0d0';
    g.fillRect(0, 0, 64, 64);
    g.fillStyle = '#ffffff';
    for (let x = 4; x < 64; x += 8) for (let y = 4; y < 64; y += 8) g.fillRect(x, y, 2, 2);
    g.fillStyle = '#303030';
    g.fillRect(22, 22, 20, 20);
  },
  checker(g) {
    for (let x = 0; x < 64; x += 16) {
      for (let y = 0; y < 64; y += 16) {
        g.fillStyle = (x + y) % 32 === 0 ? '#ffffff' : '#8c8c8c';
        g.fillRect(x, y, 16, 16);
      }
    }
  },
};
const textures = new Map();

function textureOf(name) {
  if (!name) return null;
  const key = Object.hasOwn(TEXTURE_PAINTERS, name) ? name : 'checker';
  if (!textures.has(key)) {
    const canvas = document.createElement('canvas');
    canvas.width = canvas.height = 64;
    TEXTURE_PAINTERS[key](canvas.getContext('2d'));
    const texture = new THREE.CanvasTexture(canvas);
    texture.colorSpace = THREE.SRGBColorSpace;
    textures.set(key, texture);
  }
  return textures.get(key);
}

function vec(a, fallback = [0, 0, 0]) {
  const v = Array.isArray(a) && a.length >= 3 ? a : fallback;
  return new THREE.Vector3(v[0], v[1], v[2]);
}

function quat(a) {
  const q = Array.isArray(a) && a.length >= 4 ? a : [1, 0, 0, 0];
  return new THREE.Quaternion(q[1], q[2], q[3], q[0]);  // header [w, x, y, z] -> three (x, y, z, w)
}

/**
 * A square grid on the XZ plane, `size` metres wide with `divisions` cells a side, each line cut into one segment
 * per cell. THREE.GridHelper draws each line as one segment, and software GL (SwiftShader) drops a segment that
 * crosses the camera's plane instead of clipping it: seen from inside the grid (every preset, a head camera)
 * the lines running away from the camera vanished and the floor showed as stripes.
 */
function segmentedGrid(size, divisions, color, opacity = 1) {
  const half = size / 2, step = size / divisions;
  const points = new Float32Array((divisions + 1) * divisions * 2 * 2 * 3);
  let k = 0;
  const put = (x, z) => { points[k++] = x; points[k++] = 0; points[k++] = z; };
  for (let i = 0; i <= divisions; i++) {
    const a = -half + i * step;
    for (let j = 0; j < divisions; j++) {
      const b0 = -half + j * step, b1 = b0 + step;
      put(a, b0); put(a, b1);  // along Z
      put(b0, a); put(b1, a);  // along X
    }
  }
  const material = new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity });
  return new THREE.LineSegments(new THREE.BufferGeometry().setAttribute('position', new THREE.BufferAttribute(points, 3)), material);
}

function geometryOf(geom) {
  const s = geom.size || [];
  switch (geom.shape) {
    case 'box': return new THREE.BoxGeometry(s[0] || 0.01, s[1] || 0.01, s[2] || 0.01);
    case 'sphere': return new THREE.SphereGeometry(s[0] || 0.01, 20, 14);
    case 'capsule': {
      // ODE's capsule: radius, length of the cylinder part along the geom's local z; three's is along y.
      const g = new THREE.CapsuleGeometry(s[0] || 0.01, s[1] || 0, 6, 14);
      g.rotateX(Math.PI / 2);
      return g;
    }
    case 'cylinder': {
      const g = new THREE.CylinderGeometry(s[0] || 0.01, s[0] || 0.01, s[1] || 0.01, 20);
      g.rotateX(Math.PI / 2);
      return g;
    }
    default: return null;
  }
}

/** True when WebGL runs on the CPU (SwiftShader, llvmpipe): every pixel costs there. */
function softwareGL() {
  const gl = document.createElement('canvas').getContext('webgl2');
  if (!gl) return false;
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
  gl.getExtension('WEBGL_lose_context')?.loseContext();
  return /swiftshader|llvmpipe|softpipe|software/i.test(name);
}

export class World {
  constructor(canvas, { fixedSize = null } = {}) {
    this.canvas = canvas;
    this.fixedSize = fixedSize;
    // Multisampling quadruples the fill cost of software GL (measured: 40 → 27 frames/s at full resolution in
    // headless chromium); there the interactive view goes without it. Rendered clips (fixedSize) keep it.
    const antialias = !!fixedSize || !softwareGL();
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias, preserveDrawingBuffer: true });
    this.antialias = antialias;
    this.basePixelRatio = fixedSize ? 1 : Math.min(window.devicePixelRatio || 1, 2);
    this.scale = 1;  // resolution scale while playing (1 = full); see setScale
    this.renderer.setPixelRatio(this.basePixelRatio);
    this.renderer.outputColorSpace = THREE.SRGBColorSpace;
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x1d2127);
    this.camera = new THREE.PerspectiveCamera(40, 16 / 9, 0.01, 200);
    this.camera.position.set(0, 0.4, 1.5);
    this.controls = fixedSize ? null : new OrbitControls(this.camera, canvas);
    if (this.controls) {
      this.controls.target.set(0, 0.2, 0);
      this.controls.enableDamping = false;
      this.controls.screenSpacePanning = true;
      this.controls.update();
    }

    const hemi = new THREE.HemisphereLight(0xdfe8ff, 0x3a3630, 1.6);
    this.scene.add(hemi);
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(-1.5, 3, 2);
    this.scene.add(sun, sun.target);
    this.sun = sun;
    // Shadows on the floor make depth readable (where a foot is, how high the robot is). They cost a second
    // pass and a floor-wide fill, too much for software GL: there they start off (the "shadows" box).
    this.renderer.shadowMap.enabled = true;
    sun.shadow.mapSize.set(1024, 1024);
    sun.shadow.bias = -0.0005;
    Object.assign(sun.shadow.camera, { left: -1, right: 1, top: 1, bottom: -1, near: 0.1, far: 10 });
    this.shadowCatcher = null;  // a plane over the floor that shows only the shadows (addFloor)
    this.shadows = !softwareGL();

    this.root = new THREE.Group();         // bodies of the shown run
    this.ghostRoot = new THREE.Group();    // a second run drawn translucent
    this.staticRoot = new THREE.Group();   // floor and static bodies
    this.scene.add(this.root, this.ghostRoot, this.staticRoot);

    const contactGeo = new THREE.SphereGeometry(0.006, 8, 6);
    const contactMat = new THREE.MeshBasicMaterial({ color: 0xff3b30, depthTest: false });
    this.contactMesh = new THREE.InstancedMesh(contactGeo, contactMat, CONTACT_CAPACITY);
    this.contactMesh.count = 0;
    this.contactMesh.renderOrder = 10;
    this.contactMesh.frustumCulled = false;
    this.contactLines = new THREE.LineSegments(
      new THREE.BufferGeometry().setAttribute('position',
        new THREE.BufferAttribute(new Float32Array(CONTACT_CAPACITY * 6), 3)),
      new THREE.LineBasicMaterial({ color: 0xffcc00, depthTest: false }));
    this.contactLines.frustumCulled = false;
    this.contactLines.renderOrder = 10;
    this.contactGroup = new THREE.Group();
    this.contactGroup.add(this.contactMesh, this.contactLines);
    this.contactGroup.visible = false;
    this.scene.add(this.contactGroup);

    this.jointLines = null;
    this.jointGroup = new THREE.Group();
    this.jointGroup.visible = false;
    this.scene.add(this.jointGroup);

    this.raycaster = new THREE.Raycaster();
    this.bodies = [];       // {name, dynamic, group, meshes, index}
    this.ghostBodies = [];
    this.byName = new Map();
    this.agents = [];
    this.preset = 'front';
    this.following = false;
    this.lastCenter = null;
    this.selected = null;
    this.pickedGeom = '';   // the geom the last pick() hit
    this.views = [];        // the Camera Manager's extra views: {id, kind, body, agent, preset, camera, eye, label}
    this.nextViewId = 1;
    this.viewport = { width: 1, height: 1 };  // the canvas in CSS pixels
    this._tmpM = new THREE.Matrix4();
    this._tmpV = new THREE.Vector3();
    this._tmpQ = new THREE.Quaternion();
    this.resize();
    if (!fixedSize) {
      new ResizeObserver(() => this.resize()).observe(canvas.parentElement);
    }
  }

  resize() {
    let w, h;
    if (this.fixedSize) {
      [w, h] = this.fixedSize;
    } else {
      const box = this.canvas.parentElement.getBoundingClientRect();
      w = Math.max(1, Math.floor(box.width));
      h = Math.max(1, Math.floor(box.height));
    }
    this.renderer.setSize(w, h, !this.fixedSize);
    if (this.fixedSize) {
      this.canvas.style.width = `${w}px`;
      this.canvas.style.height = `${h}px`;
    }
    this.viewport = { width: w, height: h };
    this.layOutViews();
    this.needsDraw = true;
  }

  /**
   * Dynamic resolution: draws at scale × the full pixel ratio (0.35–1). The page lowers it while playing when
   * frames come slower than the display's (software GL on a busy machine) and restores it when paused.
   */
  setScale(scale) {
    const s = Math.max(0.35, Math.min(1, scale));
    if (this.fixedSize || Math.abs(s - this.scale) < 1e-3) return;
    this.scale = s;
    this.renderer.setPixelRatio(this.basePixelRatio * s);
    this.needsDraw = true;
  }

  static disposeGroup(group) {
    group.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
      if (o.material) (Array.isArray(o.material) ? o.material : [o.material]).forEach((m) => m.dispose());
    });
    group.clear();
  }

  /** Builds the meshes of a header's bodies. `ghost` draws them translucent and unpickable. */
  buildBodies(header, ghost = false) {
    const list = [];
    const target = ghost ? this.ghostRoot : this.root;
    (header.bodies || []).forEach((body, index) => {
      const group = new THREE.Group();
      group.name = body.name;
      group.position.copy(vec(body.position));
      group.quaternion.copy(quat(body.quaternion));
      const meshes = [];
      let isFloor = false;
      for (const geom of body.geoms || []) {
        if (geom.shape === 'plane') {
          isFloor = true;
          if (!ghost) this.addFloor(body, geom);
          continue;
        }
        const geometry = geometryOf(geom);
        if (!geometry) continue;
        const { color, opacity } = colorOf(geom.color);
        const material = new THREE.MeshLambertMaterial({ color, map: ghost ? null : textureOf(geom.texture) });
        if (ghost) {
          material.transparent = true;
          material.opacity = 0.28;
          material.depthWrite = false;
          material.color.lerp(new THREE.Color(0x66ccff), 0.5);
        } else if (opacity < 1) {
          material.transparent = true;
          material.opacity = opacity;
          material.depthWrite = opacity > 0.5;
        }
        if (!ghost && opacity === 0) material.visible = false;
        const mesh = new THREE.Mesh(geometry, material);
        mesh.castShadow = !ghost && opacity > 0;
        mesh.position.copy(vec(geom.offset));
        mesh.quaternion.copy(quat(geom.rotation));
        mesh.userData.body = body.name;
        mesh.userData.geom = geom.name || '';
        if (geom.texture) mesh.userData.texture = geom.texture;
        group.add(mesh);
        meshes.push(mesh);
      }
      if (isFloor && meshes.length === 0) return;
      const p = Array.isArray(body.pose_channels) && body.pose_channels.length === 7 ? body.pose_channels : null;
      const entry = { name: body.name, index, dynamic: !!body.dynamic && !!p, poseChannels: p, group, meshes };
      (body.dynamic || ghost ? target : this.staticRoot).add(group);
      list.push(entry);
    });
    return list;
  }

  addFloor(body, geom) {
    const { color } = colorOf(geom.color && geom.color.length ? geom.color : [120, 124, 130, 255]);
    const y = (body.position && body.position[1]) || 0;
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(40, 40),
      // Unlit: the floor fills most of the view, and software GL pays per pixel for lighting.
      new THREE.MeshBasicMaterial({ color: color.clone().multiplyScalar(0.62) }));
    floor.rotation.x = -Math.PI / 2;
    floor.position.y = y;
    floor.userData.floor = true;
    const grid = segmentedGrid(4, 40, 0x6c7380, 0.35);
    grid.position.y = y + 0.0005;
    const major = segmentedGrid(20, 20, 0x4f5662);
    major.position.y = y + 0.0008;
    const catcher = new THREE.Mesh(new THREE.PlaneGeometry(40, 40), new THREE.ShadowMaterial({ opacity: 0.35 }));
    catcher.rotation.x = -Math.PI / 2;
    catcher.position.y = y + 0.0002;
    catcher.receiveShadow = true;
    this.shadowCatcher = catcher;
    this.staticRoot.add(floor, catcher, grid, major);
    this.setShadows(this.shadows);
  }

  /** Replaces the world by a recording header's bodies, joints and agents. */
  load(header) {
    World.disposeGroup(this.root);
    World.disposeGroup(this.staticRoot);
    this.clearGhost();
    this.header = header;
    this.bodies = this.buildBodies(header);
    this.byName = new Map(this.bodies.map((b) => [b.name, b]));
    this.agents = (header.agents || []).map((a) => a.name);
    this.hasFloor = (header.bodies || []).some((b) => (b.geoms || []).some((g) => g.shape === 'plane'));
    if (!this.hasFloor) {
      const grid = segmentedGrid(10, 100, 0x4a515c);
      this.staticRoot.add(grid);
    }
    this.buildJoints(header);
    this.selected = null;
    this.lastCenter = null;
    this.needsDraw = true;
  }

  loadGhost(header) {
    this.clearGhost();
    this.ghostBodies = this.buildBodies(header, true);
    this.needsDraw = true;
  }

  clearGhost() {
    World.disposeGroup(this.ghostRoot);
    this.ghostBodies = [];
    this.needsDraw = true;
  }

  buildJoints(header) {
    World.disposeGroup(this.jointGroup);
    this.joints = [];
    for (const joint of header.joints || []) {
      if (!Array.isArray(joint.anchor) || !Array.isArray(joint.axis)) continue;
      const body = this.byName.get(joint.body1) || this.byName.get(joint.body2);
      const anchor = vec(joint.anchor);
      const axis = vec(joint.axis).normalize();
      let localAnchor = anchor.clone(), localAxis = axis.clone();
      if (body) {
        const hb = header.bodies[body.index];
        const q0inv = quat(hb.quaternion).invert();
        localAnchor = anchor.clone().sub(vec(hb.position)).applyQuaternion(q0inv);
        localAxis = axis.clone().applyQuaternion(q0inv);
      }
      this.joints.push({ name: joint.name, body, localAnchor, localAxis });
    }
    const positions = new Float32Array(Math.max(1, this.joints.length) * 6);
    const geometry = new THREE.BufferGeometry().setAttribute('position', new THREE.BufferAttribute(positions, 3));
    this.jointLines = new THREE.LineSegments(geometry,
      new THREE.LineBasicMaterial({ color: 0x4cd964, depthTest: false }));
    this.jointLines.renderOrder = 11;
    this.jointLines.frustumCulled = false;
    const dots = new THREE.InstancedMesh(new THREE.SphereGeometry(0.004, 8, 6),
      new THREE.MeshBasicMaterial({ color: 0x4cd964, depthTest: false }), Math.max(1, this.joints.length));
    dots.renderOrder = 11;
    dots.count = this.joints.length;
    dots.frustumCulled = false;
    this.jointDots = dots;
    this.jointGroup.add(this.jointLines, dots);
  }

  /** Poses the dynamic bodies from a channel accessor value(channelIndex). */
  pose(value, ghost = false) {
    const list = ghost ? this.ghostBodies : this.bodies;
    for (const b of list) {
      if (!b.dynamic) continue;
      const p = b.poseChannels;
      const qw = value(p[3]), qx = value(p[4]), qy = value(p[5]), qz = value(p[6]);
      const px = value(p[0]), py = value(p[1]), pz = value(p[2]);
      if (![px, py, pz, qw, qx, qy, qz].every(Number.isFinite)) continue;
      b.group.position.set(px, py, pz);
      b.group.quaternion.set(qx, qy, qz, qw);
      const n = Math.hypot(qx, qy, qz, qw);
      if (n > 0 && Math.abs(n - 1) > 1e-3) b.group.quaternion.normalize();
    }
    if (!ghost) this.updateJoints();
    this.needsDraw = true;
  }

  updateJoints() {
    if (!this.jointGroup.visible || !this.joints) return;
    const pos = this.jointLines.geometry.attributes.position;
    const a = this._tmpV, d = new THREE.Vector3();
    this.joints.forEach((j, i) => {
      a.copy(j.localAnchor);
      d.copy(j.localAxis);
      if (j.body) {
        a.applyQuaternion(j.body.group.quaternion).add(j.body.group.position);
        d.applyQuaternion(j.body.group.quaternion);
      }
      d.multiplyScalar(0.035);
      pos.setXYZ(2 * i, a.x - d.x, a.y - d.y, a.z - d.z);
      pos.setXYZ(2 * i + 1, a.x + d.x, a.y + d.y, a.z + d.z);
      this._tmpM.makeTranslation(a.x, a.y, a.z);
      this.jointDots.setMatrixAt(i, this._tmpM);
    });
    pos.needsUpdate = true;
    this.jointDots.instanceMatrix.needsUpdate = true;
  }

  /** Shadows of the bodies on the floor, from the light above the robot. */
  setShadows(on) {
    this.shadows = !!on;
    this.sun.castShadow = this.shadows;
    if (this.shadowCatcher) this.shadowCatcher.visible = this.shadows;
    this.needsDraw = true;
  }

  /** Keeps the light's shadow box on the first robot as it moves. */
  aimLight() {
    if (!this.shadows) return;
    const c = this.robotCenter(this._tmpV);
    this.sun.target.position.copy(c);
    this.sun.position.set(c.x - 1.5, c.y + 3, c.z + 2);
  }

  setJointsVisible(on) { this.jointGroup.visible = on; this.updateJoints(); this.needsDraw = true; }
  setContactsVisible(on) { this.contactGroup.visible = on; this.needsDraw = true; }
  setBodiesVisible(on) { this.root.visible = on; this.needsDraw = true; }
  setGhostVisible(on) { this.ghostRoot.visible = on; this.needsDraw = true; }

  /** Contacts as [body1, body2, px, py, pz, nx, ny, nz, depth] rows. */
  setContacts(rows) {
    const n = Math.min(rows.length, CONTACT_CAPACITY);
    const lines = this.contactLines.geometry.attributes.position;
    for (let i = 0; i < n; i++) {
      const c = rows[i];
      this._tmpM.makeTranslation(c[2], c[3], c[4]);
      this.contactMesh.setMatrixAt(i, this._tmpM);
      lines.setXYZ(2 * i, c[2], c[3], c[4]);
      lines.setXYZ(2 * i + 1, c[2] + c[5] * 0.03, c[3] + c[6] * 0.03, c[4] + c[7] * 0.03);
    }
    this.contactMesh.count = n;
    this.contactMesh.instanceMatrix.needsUpdate = true;
    this.contactLines.geometry.setDrawRange(0, 2 * n);
    lines.needsUpdate = true;
    this.needsDraw = true;
  }

  /** The drawn pose of every body, for the page's state object. */
  poses(out = {}) {
    for (const b of this.bodies) {
      const p = b.group.position, q = b.group.quaternion;
      const e = out[b.name] || (out[b.name] = { position: [0, 0, 0], quaternion: [1, 0, 0, 0] });
      e.position[0] = p.x; e.position[1] = p.y; e.position[2] = p.z;
      e.quaternion[0] = q.w; e.quaternion[1] = q.x; e.quaternion[2] = q.y; e.quaternion[3] = q.z;
    }
    return out;
  }

  /** The centre of a robot (default the first; the mean of its bodies), else of the dynamic bodies, else the origin. */
  robotCenter(target = new THREE.Vector3(), agent = this.agents[0]) {
    let chosen = agent ? this.bodies.filter((b) => b.name.startsWith(agent + '/')) : [];
    if (!chosen.length) chosen = this.bodies.filter((b) => b.dynamic);
    target.set(0, 0, 0);
    if (!chosen.length) return target.set(0, 0.2, 0);
    for (const b of chosen) target.add(b.group.position);
    return target.multiplyScalar(1 / chosen.length);
  }

  robotSize(agent = this.agents[0]) {
    const chosen = agent ? this.bodies.filter((b) => b.name.startsWith(agent + '/')) : this.bodies.filter((b) => b.dynamic);
    if (!chosen.length) return 0.5;
    const box = new THREE.Box3();
    for (const b of chosen) box.expandByObject(b.group);
    const size = box.getSize(new THREE.Vector3());
    return Math.max(0.25, Math.min(3, Math.max(size.x, size.y, size.z)));
  }

  /**
   * Camera presets of the original: front, back, left, right, top, follow (front-right, tracking). `distance` is
   * the camera's distance in robot sizes (3 leaves room to move around; stills and clips frame closer).
   */
  setPreset(name, distance = 3) {
    const c = this.robotCenter();
    const d = this.robotSize() * distance;
    const o = PRESET_OFFSETS[name] || PRESET_OFFSETS.front;
    this.preset = name in PRESET_OFFSETS ? name : 'front';
    this.following = this.preset === 'follow';
    this.camera.position.set(c.x + o[0] * d, c.y + o[1] * d, c.z + o[2] * d);
    this.camera.up.copy(UP);
    this.lookAt(c);
    this.lastCenter = c.clone();
    this.needsDraw = true;
  }

  lookAt(c) {
    if (this.controls) {
      this.controls.target.copy(c);
      this.controls.update();
    } else {
      this.camera.lookAt(c);
    }
  }

  /** Keeps the camera's offset to the robot while following. */
  follow() {
    if (!this.following) return;
    const c = this.robotCenter();
    if (this.lastCenter) {
      const delta = this._tmpV.copy(c).sub(this.lastCenter);
      if (delta.lengthSq() > 0) {
        this.camera.position.add(delta);
        this.lookAt(c);
        this.needsDraw = true;
      }
    }
    this.lastCenter = c.clone();
  }

  /** The body under a client-space point, or null. */
  pick(clientX, clientY) {
    const rect = this.canvas.getBoundingClientRect();
    const mainWidth = rect.width * this.mainShare();  // the main view is the left column
    if (clientX - rect.left > mainWidth) return null;
    const ndc = new THREE.Vector2(((clientX - rect.left) / mainWidth) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const meshes = [];
    for (const b of this.bodies) if (b.group.parent && b.group.parent.visible) meshes.push(...b.meshes);
    const hits = this.raycaster.intersectObjects(meshes, false).filter((h) => h.object.material.visible);
    // Which of the body's geoms was hit: a body's name can hide what one sees (the A-Series' pelvis is
    // Middle/InvisiblePart, an invisible box carrying the hip servos and plate).
    this.pickedGeom = hits.length ? hits[0].object.userData.geom : '';
    return hits.length ? hits[0].object.userData.body : null;
  }

  /** Where body `name`'s origin is drawn in the main view, in client pixels {x, y}; null when it is not in the world. */
  screenOf(name) {
    const body = this.byName.get(name);
    if (!body) return null;
    const p = body.group.getWorldPosition(new THREE.Vector3()).project(this.camera);
    const rect = this.canvas.getBoundingClientRect();
    const width = rect.width * this.mainShare();
    return { x: rect.left + ((p.x + 1) / 2) * width, y: rect.top + ((1 - p.y) / 2) * rect.height };
  }

  highlight(name) {
    if (this.selected) for (const m of this.selected.meshes) m.material.emissive.setHex(0x000000);
    this.selected = name ? this.byName.get(name) || null : null;
    if (this.selected) for (const m of this.selected.meshes) m.material.emissive.setHex(0x3a6ea5);
    this.needsDraw = true;
  }

  // --- the Camera Manager ---------------------------------------------------------------------------------
  /**
   * Adds a view beside the main one and returns its id (null when there are MAX_VIEWS already or the body is not
   * in the world). `spec.kind`:
   *  - 'body': a camera fixed to `spec.body`, at the front of its geoms looking along its +Z — on a robot's
   *    Middle/Head, what the head sees (the original's head camera);
   *  - 'follow': keeps its offset to robot `spec.agent` (default the first) as it moves;
   *  - 'preset': a fixed camera at preset `spec.preset` (front, back, left, right, top).
   * `spec.label` names it over its picture.
   */
  addView(spec) {
    if (this.views.length >= MAX_VIEWS || !spec || typeof spec !== 'object') return null;
    const view = { id: this.nextViewId++, kind: String(spec.kind), camera: new THREE.PerspectiveCamera(50, 1, 0.005, 200) };
    if (view.kind === 'body') {
      const body = this.byName.get(String(spec.body));
      if (!body) return null;
      view.body = body.name;
      view.eye = this.frontOf(body);
      view.camera.fov = 60;
      view.label = `${body.name} camera`;
    } else if (view.kind === 'follow') {
      view.agent = this.agents.includes(spec.agent) ? spec.agent : this.agents[0];
      view.label = `follow ${view.agent || 'the bodies'}`;
    } else if (view.kind === 'preset' && spec.preset in PRESET_OFFSETS) {
      view.preset = spec.preset;
      view.label = spec.preset;
      this.placeAtPreset(view.camera, view.preset);
    } else {
      return null;
    }
    if (spec.label) view.label = String(spec.label);
    this.views.push(view);
    this.layOutViews();
    this.needsDraw = true;
    return view.id;
  }

  removeView(id) {
    this.views = this.views.filter((v) => v.id !== id);
    this.layOutViews();
    this.needsDraw = true;
  }

  /** The extra views as the page's state shows them. */
  viewList() {
    return this.views.map(({ id, kind, body, agent, preset, label }) => ({ id, kind, body, agent, preset, label }));
  }

  /** The share of the canvas' width the main view gets: all of it alone, else an equal column. */
  mainShare() { return 1 / (1 + this.views.length); }

  /** Where a body's camera sits in the body's frame: the middle of the front face (+Z) of its geoms, 2 mm out. */
  frontOf(body) {
    const box = new THREE.Box3();
    for (const mesh of body.meshes) {
      if (!mesh.geometry.boundingBox) mesh.geometry.computeBoundingBox();
      mesh.updateMatrix();
      box.union(mesh.geometry.boundingBox.clone().applyMatrix4(mesh.matrix));
    }
    if (box.isEmpty()) return new THREE.Vector3(0, 0, 0);
    const centre = box.getCenter(new THREE.Vector3());
    return new THREE.Vector3(centre.x, centre.y, box.max.z + 0.002);
  }

  placeAtPreset(camera, preset, agent = this.agents[0]) {
    const c = this.robotCenter(new THREE.Vector3(), agent);
    const d = this.robotSize(agent) * 3;
    const o = PRESET_OFFSETS[preset];
    camera.position.set(c.x + o[0] * d, c.y + o[1] * d, c.z + o[2] * d);
    camera.up.copy(UP);
    camera.lookAt(c);
  }

  /** Moves the cameras that go with a body or a robot to where it is now. */
  poseViewCameras() {
    for (const view of this.views) {
      if (view.kind === 'body') {
        const body = this.byName.get(view.body);
        if (!body) continue;  // the world was loaded anew without it: the view stays where it was
        body.group.updateMatrix();
        view.camera.position.copy(view.eye).applyMatrix4(body.group.matrix);
        view.camera.quaternion.copy(body.group.quaternion).multiply(LOOK_FORWARD);
      } else if (view.kind === 'follow') {
        this.placeAtPreset(view.camera, 'follow', view.agent);
      }
    }
  }

  /** Columns of equal width, the main view first; each camera's aspect follows its column. */
  layOutViews() {
    const { width, height } = this.viewport;
    const column = width / (1 + this.views.length);
    for (const camera of [this.camera, ...this.views.map((v) => v.camera)]) {
      camera.aspect = column / Math.max(1, height);
      camera.updateProjectionMatrix();
    }
    this.placeViewLabels(column);
  }

  /** A label over each extra view, with a button that closes it (the canvas' parent holds them). */
  placeViewLabels(column) {
    const parent = this.canvas.parentElement;
    if (!parent || this.fixedSize) return;
    for (const old of parent.querySelectorAll('.view-label')) old.remove();
    this.views.forEach((view, i) => {
      const label = document.createElement('div');
      label.className = 'view-label';
      label.dataset.view = String(view.id);
      label.style.left = `${(i + 1) * column + 8}px`;
      label.textContent = view.label;
      const close = document.createElement('button');
      close.textContent = '×';
      close.title = 'close this view';
      close.addEventListener('click', () => this.removeView(view.id));
      label.append(close);
      parent.append(label);
    });
  }

  render() {
    this.aimLight();
    if (!this.views.length) {
      this.renderer.render(this.scene, this.camera);
      this.needsDraw = false;
      return;
    }
    this.poseViewCameras();
    const { width, height } = this.viewport;
    const column = width / (1 + this.views.length);
    this.renderer.setScissorTest(true);
    [this.camera, ...this.views.map((v) => v.camera)].forEach((camera, i) => {
      const x = Math.round(i * column), w = Math.round((i + 1) * column) - x;
      this.renderer.setViewport(x, 0, w, height);
      this.renderer.setScissor(x, 0, w, height);
      this.renderer.render(this.scene, camera);
    });
    this.renderer.setScissorTest(false);
    this.renderer.setViewport(0, 0, width, height);
    this.needsDraw = false;
  }
}

