// The specimen and each test's snapshots in 3D (three.js): grains as
// instanced spheres, the wire as a chain of cylinders coloured by segment
// strain, the membrane translucent, the force network as cylinders between
// the bodies' centres with a radius proportional to the normal force, a
// snapshot slider, orbit/zoom, and a cut-away half. Clumps (a job with
// specimen.grain_shape) are drawn as their spheres, coloured per clump from
// the specimen's grain_clump. Positions arrive as
// float32 arrays from the result data routes; the scene is in millimetres.
//
// The wire lies inside the packing, so the grains can be drawn small (a
// third of their radius: the packing stays readable and the wire shows
// between them; the default when there is a wire) or not at all, and the
// cut-away removes the half of the grains, membrane and forces towards the
// camera, wherever it has orbited to; the wire is never cut. A colour bar
// gives the strain scale. The camera frames the specimen's bounding sphere.
import * as THREE from '../vendor/three.module.js';
import { OrbitControls } from '../vendor/OrbitControls.js';
import { json, array } from './api.js';
import { el, replace, num } from './dom.js';

const mm = 1000;
/// How large the grains are drawn in the "small" mode, as a fraction of their radius.
const smallGrainScale = 1 / 3;
const zAxis = new THREE.Vector3(0, 1, 0);  // CylinderGeometry's axis

/// Blue (most compressed) – white – red (most stretched), symmetric about 0.
function strainColour(e, maxAbs, out) {
  const t = maxAbs > 0 ? Math.max(-1, Math.min(1, e / maxAbs)) : 0;
  if (t >= 0) out.setRGB(1, 1 - t, 1 - t);
  else out.setRGB(1 + t, 1 + t, 1);
  return out;
}

/// A clump's colour: earthy hues a golden-ratio step apart, so neighbouring
/// clump indices differ; the colour of the spheres for a free grain (−1).
function clumpColour(k, out) {
  if (k < 0) return out.set(0xb39b72);
  return out.setHSL((0.07 + 0.618034 * k) % 1, 0.42, 0.56);
}

/// Instanced cylinders from a[i] to b[i] with radius r[i]; colour per instance.
function cylinders(count, ends, radius, colour, material) {
  const mesh = new THREE.InstancedMesh(new THREE.CylinderGeometry(1, 1, 1, 8, 1), material, Math.max(1, count));
  mesh.count = count;
  placeCylinders(mesh, ends, radius);
  const c = new THREE.Color();
  if (colour) for (let i = 0; i < count; ++i) mesh.setColorAt(i, colour(i, c));
  return mesh;
}

/// Sets each cylinder's matrix: from a[i] to b[i], radius r[i].
function placeCylinders(mesh, ends, radius) {
  const m = new THREE.Matrix4(), q = new THREE.Quaternion(), dir = new THREE.Vector3(), mid = new THREE.Vector3(), s = new THREE.Vector3();
  const a = new THREE.Vector3(), b = new THREE.Vector3();
  for (let i = 0; i < mesh.count; ++i) {
    ends(i, a, b);
    dir.subVectors(b, a);
    const len = dir.length();
    if (len > 0) q.setFromUnitVectors(zAxis, dir.divideScalar(len)); else q.identity();
    mid.addVectors(a, b).multiplyScalar(0.5);
    const r = radius(i);
    m.compose(mid, q, s.set(r, len, r));
    mesh.setMatrixAt(i, m);
  }
  mesh.instanceMatrix.needsUpdate = true;
  mesh.boundingSphere = null;
  mesh.boundingBox = null;
}

/// The wire segments gone in the state shown (segment s joins nodes s and
/// s + 1): those between the prepared wire's pieces (summary.specimen.wire_pieces:
/// cut or broken in the preparation) and, for a snapshot, those its test broke
/// by the snapshot's time (the test's wire_breaks, time_s on the test's clock
/// as the snapshot's). A Set of segment indices; empty for a whole wire.
export function removedWireSegments(summary, wireNodes, test, snap) {
  const gone = new Set();
  const pieces = summary?.specimen?.wire_pieces;
  if (Array.isArray(pieces) && pieces.length) {
    const kept = new Set();
    for (const p of pieces) for (let s = p.first_node; s < p.first_node + p.nodes - 1; ++s) kept.add(s);
    for (let s = 0; s < wireNodes - 1; ++s) if (!kept.has(s)) gone.add(s);
  }
  if (test && snap) {
    const pressure = test.attributes?.confining_pressure_pa;
    const t = (summary?.tests || []).find((x) => x.confining_pressure_pa === pressure);
    for (const b of t?.wire_breaks || []) if (b.time_s <= snap.time_s) gone.add(b.segment);
  }
  return gone;
}

export class View3d {
  constructor(parent, job, tests, summary = null) {
    this.job = job;
    this.tests = tests;
    this.summary = summary;
    this.canvas = el('canvas', { id: 'view3d-canvas', 'aria-label': '3D view of the specimen' });
    this.source = el('select', { id: 'view3d-source', 'aria-label': 'what to show' },
      el('option', { value: 'specimen' }, 'prepared specimen'),
      tests.map((t, i) => el('option', { value: i }, `test at σ₃ = ${num(t.attributes.confining_pressure_pa / 1000, 4)} kPa`)));
    this.slider = el('input', { type: 'range', id: 'view3d-snapshot', min: 0, max: 0, step: 1, value: 0, disabled: true, 'aria-label': 'snapshot' });
    this.sliderLabel = el('span', { id: 'view3d-snapshot-label' }, '');
    this.toggles = {};
    this.grainMode = el('select', { id: 'view3d-grain-mode', 'aria-label': 'how the grains are drawn' },
      el('option', { value: 'small' }, 'small (the wire shows)'), el('option', { value: 'solid' }, 'full size'),
      el('option', { value: 'none' }, 'hidden'));
    this.grainMode.addEventListener('change', () => { this.grainModeChosen = true; this.applyToggles(); });
    this.colourBar = el('div', { class: 'colour-bar', id: 'view3d-colour-bar', hidden: true },
      el('span', { class: 'colour-bar-title' }, 'wire segment strain'),
      el('span', { class: 'colour-bar-end', id: 'view3d-colour-min' }, ''), el('span', { class: 'colour-bar-ramp' }),
      el('span', { class: 'colour-bar-end', id: 'view3d-colour-max' }, ''),
      el('span', { class: 'muted' }, 'blue compressed · white 0 · red stretched'));
    const toggle = (key, label, on) => {
      const box = el('input', { type: 'checkbox', checked: on, id: `view3d-${key}` });
      box.addEventListener('change', () => this.applyToggles());
      this.toggles[key] = box;
      return el('label', {}, box, ` ${label}`);
    };
    this.info = el('span', { class: 'muted', id: 'view3d-info' });
    this.error = el('div');
    parent.append(el('h2', {}, '3D view'), el('div', { class: 'view3d' },
      el('div', { class: 'controls' }, el('label', {}, 'Show ', this.source), el('label', {}, 'Snapshot ', this.slider), this.sliderLabel,
        el('label', {}, 'Grains ', this.grainMode), toggle('wire', 'wire', true), toggle('membrane', 'membrane', true),
        toggle('forces', 'force network', true), toggle('cut', 'cut away half', false)),
      this.error, this.canvas, this.colourBar, this.info));

    try {
      this.renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: true, preserveDrawingBuffer: true });
    } catch (e) {
      replace(this.error, el('div', { class: 'error-box' }, `No WebGL here: ${e.message}`));
      this.ready = Promise.resolve();
      return;
    }
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(0xf2f4f7);
    this.scene = new THREE.Scene();
    this.scene.add(new THREE.AmbientLight(0xffffff, 1.2));
    const sun = new THREE.DirectionalLight(0xffffff, 2.2);
    sun.position.set(1, -2, 3);
    this.scene.add(sun);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.1, 1e5);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('change', () => this.render());
    this.group = new THREE.Group();
    this.scene.add(this.group);
    // Keeps what lies beyond the orbit's target as seen from the camera (set in render()).
    this.cut = new THREE.Plane(new THREE.Vector3(0, 1, 0), 0);
    this.resize = () => this.fit();
    window.addEventListener('resize', this.resize);
    this.source.addEventListener('change', () => this.select());
    this.slider.addEventListener('input', () => this.load());
    this.framed = false;
    // First the end of the test at the highest pressure: the wire strained most, the force network loaded.
    if (tests.some((t) => t.snapshots.length)) this.source.value = String(tests.length - 1);
    this.ready = this.select();
  }

  fit() {
    const w = this.canvas.clientWidth || 800, h = this.canvas.clientHeight || 520;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  select() {
    const t = this.source.value === 'specimen' ? null : this.tests[Number(this.source.value)];
    this.slider.disabled = !t || t.snapshots.length < 2;
    this.slider.max = t ? Math.max(0, t.snapshots.length - 1) : 0;
    this.slider.value = t ? this.slider.max : 0;  // the end of the test: the most developed state
    return this.load();
  }

  /// Fetches the arrays of the chosen specimen or snapshot and rebuilds the scene.
  async load() {
    const t = this.source.value === 'specimen' ? null : this.tests[Number(this.source.value)];
    const snap = t ? t.snapshots[Number(this.slider.value)] : null;
    const url = snap ? snap.url : `/v1/jobs/${this.job.id}/specimen`;
    this.sliderLabel.textContent = snap ? `ε₁ = ${num(snap.axial_strain, 3)} (requested ${num(snap.requested_axial_strain, 3)})` : '';
    const token = (this.loading = {});
    try {
      const group = await json(url);
      const names = new Set(group.arrays.map((a) => a.name));
      const get = (name) => (names.has(name) ? array(`${url}/${name}`) : Promise.resolve(null));
      // The specimen has no triangles of its own: the membrane mesh is the same in every snapshot.
      const firstSnap = this.tests.find((x) => x.snapshots.length)?.snapshots[0];
      const triangles = names.has('membrane_triangles') ? get('membrane_triangles') : firstSnap ? array(`${firstSnap.url}/membrane_triangles`).catch(() => null) : null;
      const [grains, radii, wire, strain, membrane, tri, bodies, force, clump] = await Promise.all([
        get('grain_position_m'), get('grain_radius_m'), get('wire_node_position_m'), get('wire_segment_strain'),
        get('membrane_node_position_m'), triangles, get('contact_bodies'), get('contact_normal_force_n'), this.clumps()]);
      if (token !== this.loading) return;  // a later choice won
      const gone = wire ? removedWireSegments(this.summary, wire.shape[0], t, snap) : new Set();
      this.build({ grains, radii, wire, strain, membrane, tri, bodies, force, clump, gone });
      replace(this.error);
    } catch (e) {
      replace(this.error, el('div', { class: 'error-box' }, `Cannot load the 3D view: ${e.message}`));
    }
  }

  /// Which clump each sphere belongs to (−1: a free grain), or null without
  /// clumps: the specimen's grain_clump (docs/results.md), which holds for
  /// every snapshot too (a snapshot's grains are the same spheres in the same
  /// order), fetched once.
  clumps() {
    if (!this.clumpsPromise) {
      const url = `/v1/jobs/${this.job.id}/specimen`;
      this.clumpsPromise = json(url).then((g) => (g.arrays.some((a) => a.name === 'grain_clump') ? array(`${url}/grain_clump`) : null));
      this.clumpsPromise.catch(() => { this.clumpsPromise = null; });  // tried again on the next load
    }
    return this.clumpsPromise;
  }

  build({ grains, radii, wire, strain, membrane, tri, bodies, force, clump, gone = new Set() }) {
    for (const child of [...this.group.children]) {
      this.group.remove(child);
      child.geometry.dispose();
      child.material.dispose();
    }
    const n = grains ? grains.shape[0] : 0;
    const pos = (arr, i, out) => out.set(arr.data[3 * i] * mm, arr.data[3 * i + 1] * mm, arr.data[3 * i + 2] * mm);
    const stats = { grains: n, wireSegments: 0, membraneTriangles: 0, contacts: 0 };
    this.meshes = {};

    const clumped = clump && clump.data.length === n && clump.data.some((k) => k >= 0);
    if (n) {
      // Double-sided: a grain the cut-away opens shows its inside, not the grains behind it.
      // Clumps: every sphere drawn, coloured by its clump (white material: the instance colour shows as it is).
      const sphere = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 20, 14),
        new THREE.MeshStandardMaterial({ color: clumped ? 0xffffff : 0xb39b72, roughness: 0.85, side: THREE.DoubleSide }), n);
      if (clumped) {
        const c = new THREE.Color();
        const ids = new Set();
        for (let i = 0; i < n; ++i) {
          const k = clump.data[i];
          if (k >= 0) ids.add(k);
          sphere.setColorAt(i, clumpColour(k, c));
        }
        stats.clumps = ids.size;
        stats.clumpSpheres = clump.data.filter((k) => k >= 0).length;
        this.clumpOf = clump.data;
      } else this.clumpOf = null;
      this.meshes.grains = sphere;
      this.grainRadii = radii.data;
      this.grainPositions = grains;
      this.group.add(sphere);
    }
    const wireRadius = (this.job.spec?.specimen?.wire?.radius_m ?? 5e-4) * mm;
    // The segments still there (a cut or broken wire's others are not drawn).
    const segs = [];
    if (wire) for (let s = 0; s + 1 < wire.shape[0]; ++s) if (!gone.has(s)) segs.push(s);
    if (segs.length) {
      let maxAbs = 0;
      if (strain) for (const s of segs) maxAbs = Math.max(maxAbs, Math.abs(strain.data[s]));
      this.meshes.wire = cylinders(segs.length, (i, x, y) => { pos(wire, segs[i], x); pos(wire, segs[i] + 1, y); }, () => wireRadius,
        (i, c) => (strain ? strainColour(strain.data[segs[i]], maxAbs, c) : c.set(0x3b4252)),
        new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.5 }));
      this.group.add(this.meshes.wire);
      stats.wireSegments = segs.length;
      stats.wireSegmentsGone = gone.size;
      stats.maxAbsStrain = maxAbs;
    }
    if (membrane && tri) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(Float32Array.from(membrane.data, (v) => v * mm), 3));
      g.setIndex(new THREE.BufferAttribute(Uint32Array.from(tri.data), 1));
      g.computeVertexNormals();
      this.meshes.membrane = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: 0x5b8fd6, transparent: true, opacity: 0.16,
        side: THREE.DoubleSide, depthWrite: false }));
      this.group.add(this.meshes.membrane);
      stats.membraneTriangles = tri.shape[0];
    }
    if (bodies && force && n) {
      const sources = [grains, wire, membrane];
      let fmax = 0;
      for (const f of force.data) fmax = Math.max(fmax, Math.abs(f));
      let rmin = Infinity;
      for (const r of radii.data) rmin = Math.min(rmin, r * mm);
      const count = bodies.shape[0];
      const end = (k, idx, out) => { const src = sources[k]; return src ? pos(src, idx, out) : out.set(0, 0, 0); };
      const ends = (i, a, b) => {
        end(bodies.data[4 * i], bodies.data[4 * i + 1], a);
        end(bodies.data[4 * i + 2], bodies.data[4 * i + 3], b);
      };
      // The chains are as thick as the grains are drawn (placeGrains scales them with the grains).
      this.placeForces = (scale) => placeCylinders(this.meshes.forces, ends,
        (i) => (fmax > 0 ? 0.45 * rmin * scale * Math.abs(force.data[i]) / fmax : 0));
      this.meshes.forces = cylinders(count, ends, (i) => (fmax > 0 ? 0.45 * rmin * Math.abs(force.data[i]) / fmax : 0), null,
      // Slate, not red: the wire's colours are the strain's.
      new THREE.MeshStandardMaterial({ color: 0x4b5563, roughness: 0.6 }));
      this.group.add(this.meshes.forces);
      stats.contacts = count;
      stats.maxNormalForceN = fmax;
    }
    this.setColourBar(stats.maxAbsStrain);
    this.canvas.wiredemView = stats;
    this.canvas.wiredemWireVisibility = () => this.wireVisibility();
    this.canvas.wiredemClumpColour = (i) => {
      if (!this.clumpOf) return null;
      const c = new THREE.Color();
      this.meshes.grains.getColorAt(i, c);
      return c.getHexString();
    };
    const grainText = stats.clumps ? `${stats.clumps} clumps of ${stats.clumpSpheres} spheres (a colour per clump)` +
      (stats.grains > stats.clumpSpheres ? ` and ${stats.grains - stats.clumpSpheres} free grains` : '') : `${stats.grains} grains`;
    this.info.textContent = `${grainText} · ${stats.wireSegments} wire segments` +
      (stats.maxAbsStrain ? ` (colour: segment strain, ±${num(stats.maxAbsStrain, 2)}, blue compressed, red stretched)` : '') +
      ` · ${stats.membraneTriangles} membrane triangles · ${stats.contacts} contacts (radius ∝ normal force)`;

    if (!this.grainModeChosen) this.grainMode.value = stats.wireSegments ? 'small' : 'solid';
    this.applyToggles();
    if (!this.framed && n) this.frame();
  }

  /// Points the camera at the specimen (its grains and wire, at full size:
  /// the membrane reaches above a column that has settled) from the side, a
  /// little above, and moves it until the box's corners span 90 % of the
  /// narrower side of the frame.
  frame() {
    const box = new THREE.Box3();
    const n = this.grainRadii.length, g = this.grainPositions.data;
    for (let i = 0; i < n; ++i) {
      const r = this.grainRadii[i] * mm;
      box.expandByPoint(new THREE.Vector3(g[3 * i] * mm - r, g[3 * i + 1] * mm - r, g[3 * i + 2] * mm - r));
      box.expandByPoint(new THREE.Vector3(g[3 * i] * mm + r, g[3 * i + 1] * mm + r, g[3 * i + 2] * mm + r));
    }
    if (this.meshes.wire) box.expandByObject(this.meshes.wire);
    const centre = box.getCenter(new THREE.Vector3());
    const corners = [0, 1, 2, 3, 4, 5, 6, 7].map((k) => new THREE.Vector3(
      k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z));
    this.fit();  // the aspect of the canvas as laid out
    const dir = new THREE.Vector3(0.62, -0.77, 0.16).normalize();
    this.controls.target.copy(centre);
    // Start from the bounding sphere's distance, then scale by how much of
    // the frame the corners take (perspective: a few rounds converge).
    let d = box.getBoundingSphere(new THREE.Sphere()).radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov) / 2);
    const ndc = new THREE.Vector3();
    for (let round = 0; round < 6; ++round) {
      this.camera.position.copy(centre).addScaledVector(dir, d);
      this.camera.near = d / 100;
      this.camera.far = d * 10;
      this.camera.lookAt(centre);
      this.camera.updateProjectionMatrix();
      this.camera.updateMatrixWorld();
      const span = Math.max(...corners.map((c) => Math.max(Math.abs(ndc.copy(c).project(this.camera).x), Math.abs(ndc.y))));
      d *= span / 0.9;
    }
    this.camera.position.copy(centre).addScaledVector(dir, d);
    this.controls.update();
    this.framed = true;
    this.render();
  }

  /// Places every grain at its radius, or a third of it, from the kept arrays.
  placeGrains() {
    const sphere = this.meshes?.grains;
    if (!sphere) return;
    const scale = this.grainMode.value === 'small' ? smallGrainScale : 1;
    if (this.grainScale === scale && sphere === this.scaledMesh) return;
    const m = new THREE.Matrix4(), p = new THREE.Vector3(), q = new THREE.Quaternion(), s = new THREE.Vector3();
    const g = this.grainPositions.data;
    for (let i = 0; i < this.grainRadii.length; ++i) {
      const r = this.grainRadii[i] * mm * scale;
      sphere.setMatrixAt(i, m.compose(p.set(g[3 * i] * mm, g[3 * i + 1] * mm, g[3 * i + 2] * mm), q, s.set(r, r, r)));
    }
    sphere.instanceMatrix.needsUpdate = true;
    sphere.computeBoundingSphere();
    sphere.computeBoundingBox();
    if (this.meshes.forces) this.placeForces(scale);
    this.grainScale = scale;
    this.scaledMesh = sphere;
  }

  /// The colour bar of the wire's strain: ±the snapshot's largest |strain|.
  setColourBar(maxAbs) {
    this.colourBar.hidden = !maxAbs;
    this.colourBar.querySelector('#view3d-colour-min').textContent = maxAbs ? `−${num(maxAbs * 1000, 2)}·10⁻³` : '';
    this.colourBar.querySelector('#view3d-colour-max').textContent = maxAbs ? `+${num(maxAbs * 1000, 2)}·10⁻³` : '';
  }

  /// The fraction of the wire's segments whose midpoint is the first thing
  /// a ray from the camera meets (what the browser test reads): the wire is
  /// seen, not hidden by grains, membrane or forces.
  wireVisibility() {
    const wire = this.meshes?.wire;
    if (!wire || !wire.visible) return 0;
    this.scene.updateMatrixWorld();
    const targets = ['grains', 'forces', 'wire'].map((k) => this.meshes[k]).filter((m) => m && m.visible);
    const ray = new THREE.Raycaster();
    const m = new THREE.Matrix4(), mid = new THREE.Vector3(), ndc = new THREE.Vector3();
    const planes = this.toggles.cut.checked ? [this.cut] : [];
    let seen = 0;
    for (let i = 0; i < wire.count; ++i) {
      wire.getMatrixAt(i, m);
      mid.setFromMatrixPosition(m);
      ndc.copy(mid).project(this.camera);
      ray.setFromCamera(ndc, this.camera);
      // The first hit that the cut-away has not removed (the wire is never cut).
      const hit = ray.intersectObjects(targets, false).find((h) => h.object === wire || planes.every((pl) => pl.distanceToPoint(h.point) >= 0));
      if (hit && hit.object === wire) ++seen;  // this segment or its neighbour at the joint
    }
    return wire.count ? seen / wire.count : 0;
  }

  applyToggles() {
    if (!this.renderer) return;
    for (const key of ['wire', 'membrane', 'forces']) if (this.meshes?.[key]) this.meshes[key].visible = this.toggles[key].checked;
    if (this.meshes?.grains) this.meshes.grains.visible = this.grainMode.value !== 'none';
    this.placeGrains();
    // Everything but the wire is cut (the wire is what the cut is for).
    const cut = this.toggles.cut.checked ? [this.cut] : [];
    for (const key of ['grains', 'membrane', 'forces']) if (this.meshes?.[key]) this.meshes[key].material.clippingPlanes = cut;
    this.renderer.localClippingEnabled = true;
    this.fit();
  }

  render() {
    if (!this.renderer) return;
    // The cut: the plane through the orbit's target facing the camera, so
    // the half towards the viewer goes whichever side it looks from.
    const towards = new THREE.Vector3().subVectors(this.controls.target, this.camera.position).normalize();
    this.cut.setFromNormalAndCoplanarPoint(towards, this.controls.target);
    this.renderer.render(this.scene, this.camera);
  }

  dispose() {
    window.removeEventListener('resize', this.resize);
    if (this.controls) this.controls.dispose();
    if (this.renderer) { this.renderer.dispose(); this.renderer.forceContextLoss(); }
  }
}
