// The report's interactive 3D view: the clean map coloured by height, the removed points in red
// and the trajectory, drawn with three.js and its OrbitControls (drag to turn, right-drag to pan,
// wheel to zoom). esbuild bundles this file with three into one script that report.py inlines,
// so the page stays self-contained and works offline.
//
// Input: elements #cloud-static, #cloud-dynamic and #cloud-trajectory holding base64 float32
// x, y, z triples (already shifted so the trajectory's centre is the origin), inside #map3d.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

function floats(id) {
  const el = document.getElementById(id);
  if (!el) return new Float32Array(0);
  const bin = atob(el.textContent.trim());
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Float32Array(bytes.buffer, 0, Math.floor(bytes.length / 12) * 3);
}

// z of the 2nd and 98th percentile: a few returns from a roof or below the road must not wash
// the colour scale out.
function heightRange(pos) {
  const n = pos.length / 3;
  if (n === 0) return [0, 1];
  const z = new Float32Array(n);
  for (let i = 0; i < n; ++i) z[i] = pos[3 * i + 2];
  z.sort();
  const lo = z[Math.floor(0.02 * (n - 1))], hi = z[Math.floor(0.98 * (n - 1))];
  return [lo, hi > lo ? hi : lo + 1];
}

// Blue (low) through green to pale yellow (high): no red, which marks the removed points.
function heightColours(pos) {
  const [lo, hi] = heightRange(pos);
  const c = new Float32Array(pos.length);
  const col = new THREE.Color();
  for (let i = 0; i < pos.length; i += 3) {
    const t = Math.min(1, Math.max(0, (pos[i + 2] - lo) / (hi - lo)));
    col.setHSL(0.62 - 0.45 * t, 0.55, 0.35 + 0.35 * t);
    c[i] = col.r; c[i + 1] = col.g; c[i + 2] = col.b;
  }
  return c;
}

function points(pos, material, colours) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  if (colours) g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  return new THREE.Points(g, material);
}

// Looks at the trajectory's middle from behind and above, far enough to see all of it and the
// street around it.
function placeCamera(camera, controls, trajectory, cloud) {
  const box = new THREE.Box3();
  box.setFromArray(trajectory.length >= 3 ? trajectory : cloud);
  if (box.isEmpty()) box.set(new THREE.Vector3(-10, -10, 0), new THREE.Vector3(10, 10, 0));
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const reach = Math.max(30, 0.6 * Math.max(size.x, size.y));
  controls.target.copy(centre);
  camera.position.set(centre.x - 0.6 * reach, centre.y - 0.9 * reach, centre.z + 0.9 * reach);
  camera.far = 20 * reach;
  camera.updateProjectionMatrix();
  controls.update();
}

function start() {
  const host = document.getElementById('map3d');
  if (!host) return;
  const width = host.clientWidth || 1000, height = Math.round(0.6 * width);
  let renderer;
  try {
    // preserveDrawingBuffer: the last frame stays in the canvas, so a screenshot shows it.
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    host.textContent = '3D view: this browser has no WebGL (' + e.message + ')';
    window.cleanmapViewer = { drawn: false, error: String(e) };
    return;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(width, height);
  renderer.setClearColor(0xffffff);
  host.appendChild(renderer.domElement);

  const stat = floats('cloud-static'), dyn = floats('cloud-dynamic'), traj = floats('cloud-trajectory');
  const scene = new THREE.Scene();
  scene.add(points(stat, new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, vertexColors: true }),
                   heightColours(stat)));
  scene.add(points(dyn, new THREE.PointsMaterial({ size: 3, sizeAttenuation: false, color: 0xe00000 })));
  if (traj.length >= 6) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(traj, 3));
    scene.add(new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0x000000 })));
  }
  const camera = new THREE.PerspectiveCamera(50, width / height, 0.1, 5000);
  camera.up.set(0, 0, 1);  // z up, as in the map
  const controls = new OrbitControls(camera, renderer.domElement);
  placeCamera(camera, controls, traj, stat);
  const draw = () => renderer.render(scene, camera);
  controls.addEventListener('change', draw);
  draw();
  window.cleanmapViewer = { drawn: true, staticPoints: stat.length / 3, removedPoints: dyn.length / 3 };
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
