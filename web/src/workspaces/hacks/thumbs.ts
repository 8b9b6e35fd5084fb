// Parts-library thumbnails: one offscreen renderer draws each part's mesh into a small image, lazily.
import * as THREE from 'three';
import type { HacksApi } from './api';
import { geometryOf } from '../../shell/scene';
import { PRIM_COLORS } from './colors';
import type { PartInfo } from './api';

const SIZE = 64;
let size = SIZE;
let renderer: THREE.WebGLRenderer | null = null;
const queue: { part: PartInfo; img: HTMLImageElement; api: HacksApi }[] = [];
let busy = false;

function draw(part: PartInfo, mesh: Awaited<ReturnType<HacksApi['mesh']>>): string {
  if (!renderer) {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true, canvas: document.createElement('canvas') });
    renderer.setPixelRatio(1); renderer.setClearColor(0xffffff);
  }
  renderer.setSize(size, size, false);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2); sun.position.set(1, -2, 3); scene.add(sun);
  const group = new THREE.Group();
  group.add(new THREE.Mesh(geometryOf(mesh.body), new THREE.MeshStandardMaterial({ color: 0xb0b0b0 })));
  for (const [name, m] of Object.entries(mesh.primitives)) {
    const type = part.primitives.find((p) => p.name === name)?.type ?? '';
    group.add(new THREE.Mesh(geometryOf(m), new THREE.MeshStandardMaterial({ color: PRIM_COLORS[type] ?? 0x999999 })));
  }
  scene.add(group);
  const box = new THREE.Box3().setFromObject(group);
  const c = box.getCenter(new THREE.Vector3()), r = Math.max(1, box.getSize(new THREE.Vector3()).length() / 2);
  const cam = new THREE.PerspectiveCamera(35, 1, r / 100, r * 100);
  cam.up.set(0, 0, 1);
  cam.position.copy(c.clone().add(new THREE.Vector3(1, -1.2, 0.9).normalize().multiplyScalar(r / Math.sin((17.5 * Math.PI) / 180))));
  cam.lookAt(c);
  renderer.render(scene, cam);
  const url = renderer.domElement.toDataURL('image/png');
  group.traverse((o) => { if ((o as THREE.Mesh).geometry) (o as THREE.Mesh).geometry.dispose(); });
  return url;
}

async function pump(): Promise<void> {
  if (busy) return;
  busy = true;
  while (queue.length) {
    const { part, img, api } = queue.shift()!;
    try { img.src = draw(part, await api.mesh(part.name)); img.dataset.state = 'done'; } catch { img.alt = 'no mesh'; img.dataset.state = 'error'; }
  }
  busy = false;
}

/** Renders the thumbnail when the image scrolls into view. */
export function lazyThumbnail(api: HacksApi, part: PartInfo, img: HTMLImageElement): void {
  img.width = SIZE; img.height = SIZE; img.dataset.state = 'pending';
  const io = new IntersectionObserver((entries) => {
    if (entries.some((e) => e.isIntersecting)) { io.disconnect(); queue.push({ part, img, api }); void pump(); }
  });
  io.observe(img);
}

const previews = new Map<string, Promise<string>>();
/** A larger picture of a part (the library's hover preview), rendered once per part. */
export function renderPreview(api: HacksApi, part: PartInfo, px: number): Promise<string> {
  if (!previews.has(part.name)) {
    previews.set(part.name, api.mesh(part.name).then((mesh) => {
      size = px;
      try { return draw(part, mesh); } finally { size = SIZE; }
    }));
  }
  return previews.get(part.name)!;
}
