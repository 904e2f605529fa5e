
const report = window.icrkitReport;
const message = (text) => { document.getElementById('viewer-message').textContent = text; };

function decodeBase64(text) {
  const binary = atob(text.trim());
  const out = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) out[i] = binary.charCodeAt(i);
  return out;
}

async function loadThree() {
  const moduleBytes = decodeBase64(document.getElementById('three-module').textContent);
  const threeUrl = URL.createObjectURL(new Blob([moduleBytes], { type: 'text/javascript' }));
  const orbitText = new TextDecoder().decode(decodeBase64(document.getElementById('three-orbit').textContent))
    .replace(/from\s*['"]three['"]/g, 'from ' + JSON.stringify(threeUrl));
  const orbitUrl = URL.createObjectURL(new Blob([orbitText], { type: 'text/javascript' }));
  const THREE = await import(threeUrl);
  const { OrbitControls } = await import(orbitUrl);
  return { THREE, OrbitControls };
}

const FINGER_COLORS = ['#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#e377c2', '#8c564b', '#bcbd22',
                       '#1f77b4', '#7f7f7f'];
const MESH_COLORS = { cad: '#bdbdbd', raw: '#d9b48f', filtered: '#9ecae1' };

async function main() {
  const data = JSON.parse(document.getElementById('viewer-data').textContent);
  const { THREE, OrbitControls } = await loadThree();
  const canvas = document.getElementById('viewer');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);

  const scene = new THREE.Scene();
  scene.background = new THREE.Color('#ffffff');
  const camera = new THREE.PerspectiveCamera(35, 1, 0.001, 100);
  camera.up.set(0, 0, 1);  // the datasets are z-up (objects stand on z = 0)
  scene.add(camera);
  scene.add(new THREE.HemisphereLight('#ffffff', '#666666', 1.6));
  // A headlight: lit from where the user looks, whatever the rotation.
  const headlight = new THREE.DirectionalLight('#ffffff', 1.8);
  const headTarget = new THREE.Object3D();
  headTarget.position.set(0, 0, -1);
  headlight.position.set(0.3, 0.4, 0);
  camera.add(headlight, headTarget);
  headlight.target = headTarget;

  const lo = data.box.min, hi = data.box.max;
  const extent = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
  const diagonal = Math.hypot(extent[0], extent[1], extent[2]) || 1;
  const fingerColors = [];
  for (let f = 0; f < data.fingers; ++f) fingerColors.push(new THREE.Color(FINGER_COLORS[f % FINGER_COLORS.length]));
  const fingerOn = fingerColors.map(() => true);

  const entries = [];
  for (const m of data.meshes) {
    const quantized = new Uint16Array(decodeBase64(m.positions).buffer);
    const positions = new Float32Array(quantized.length);
    for (let i = 0; i < quantized.length; i += 3)
      for (let a = 0; a < 3; ++a) positions[i + a] = lo[a] + (quantized[i + a] / 65535) * extent[a];
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(decodeBase64(m.faces).buffer), 1));
    geometry.computeVertexNormals();
    const colors = new Float32Array(positions.length);
    geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
    // Reconstructed meshes are not consistently oriented: light both sides.
    const material = new THREE.MeshStandardMaterial({ vertexColors: true, side: THREE.DoubleSide, roughness: 0.85,
                                                      metalness: 0.0 });
    const group = new THREE.Group();
    group.add(new THREE.Mesh(geometry, material));
    const spheres = [];
    m.contacts.forEach((p, finger) => {
      if (!p) return;
      const sphere = new THREE.Mesh(new THREE.SphereGeometry(0.015 * diagonal, 16, 12),
                                    new THREE.MeshStandardMaterial({ color: fingerColors[finger].clone().multiplyScalar(0.6) }));
      sphere.position.set(p[0], p[1], p[2]);
      sphere.userData.finger = finger;
      spheres.push(sphere);
      group.add(sphere);
    });
    scene.add(group);
    entries.push({ key: m.key, group, geometry, colors, spheres, base: new THREE.Color(MESH_COLORS[m.key] || '#cccccc'),
                   region: m.region ? new Int8Array(decodeBase64(m.region).buffer) : null });
  }

  const controls = new OrbitControls(camera, canvas);
  const render = () => renderer.render(scene, camera);
  controls.addEventListener('change', render);

  function paint() {
    for (const e of entries) {
      const n = e.colors.length / 3;
      for (let v = 0; v < n; ++v) {
        const f = e.region ? e.region[v] : -1;
        const c = f >= 0 && fingerOn[f] ? fingerColors[f] : e.base;
        e.colors[3 * v] = c.r; e.colors[3 * v + 1] = c.g; e.colors[3 * v + 2] = c.b;
      }
      e.geometry.attributes.color.needsUpdate = true;
      for (const s of e.spheres) s.visible = fingerOn[s.userData.finger];
    }
  }

  // Side by side (default): the meshes in a row along x, so that regions on
  // nearly coincident surfaces do not hide each other; overlaid: as measured.
  function arrange() {
    const sideBySide = document.getElementById('layout-side').checked;
    const shown = entries.filter((e) => e.group.visible);
    for (const e of entries) e.group.position.set(0, 0, 0);
    if (sideBySide) shown.forEach((e, i) => { e.group.position.x = (i - (shown.length - 1) / 2) * extent[0] * 1.3; });
  }

  function fit() {
    const box = new THREE.Box3();
    for (const e of entries) if (e.group.visible) box.expandByObject(e.group);
    if (box.isEmpty()) box.set(new THREE.Vector3(...lo), new THREE.Vector3(...hi));
    const center = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    // Frame the row of meshes in both directions: the canvas is wide, so the
    // vertical field of view alone would leave them small.
    const halfV = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
    const halfH = halfV * camera.aspect;
    const halfWidth = Math.hypot(size.x, 0.3 * size.y) / 2, halfHeight = Math.hypot(size.z, size.y) / 2;
    const distance = (Math.max(halfWidth / halfH, halfHeight / halfV) * 1.3 + size.y / 2) || 1;
    const direction = new THREE.Vector3(0.25, -1, 0.55).normalize();
    camera.position.copy(center).addScaledVector(direction, distance);
    camera.near = distance / 200;
    camera.far = distance * 20;
    camera.updateProjectionMatrix();
    controls.target.copy(center);
    controls.update();
  }

  function resize() {
    const width = canvas.clientWidth || 800, height = canvas.clientHeight || 560;
    renderer.setSize(width, height, false);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
    render();
  }

  for (const e of entries) {
    const box = document.getElementById('mesh-' + e.key);
    if (box) box.addEventListener('change', () => { e.group.visible = box.checked; arrange(); render(); });
  }
  fingerOn.forEach((_, f) => {
    const box = document.getElementById('finger-' + f);
    if (box) box.addEventListener('change', () => { fingerOn[f] = box.checked; paint(); render(); });
  });
  for (const id of ['layout-side', 'layout-overlay'])
    document.getElementById(id).addEventListener('change', () => { arrange(); fit(); render(); });
  document.getElementById('view-reset').addEventListener('click', () => { fit(); render(); });
  window.addEventListener('resize', resize);

  paint();
  arrange();
  resize();
  fit();
  render();
  const rect = canvas.getBoundingClientRect();
  report.canvas = { x: Math.round(rect.left + window.scrollX), y: Math.round(rect.top + window.scrollY),
                    width: Math.round(rect.width), height: Math.round(rect.height) };
  report.triangles = renderer.info.render.triangles;
  report.viewer = 'rendered';
  report.ready = true;
  report.update();
  message('Drag to rotate, scroll to zoom, right-drag to pan.');
}

main().catch((error) => {
  report.errors.push('viewer: ' + (error && error.message ? error.message : String(error)));
  report.viewer = 'failed';
  report.ready = true;
  report.update();
  message('3D viewer failed: ' + (error && error.message ? error.message : String(error)));
});
