// Template-library thumbnails: one offscreen renderer draws each design's parts (in their
// materials, from GET library/{design}/mesh) into a small image when it scrolls into view.
import * as THREE from 'three';
import type { TemplatesApi } from './api';
import { geometryOf } from '../../shell/scene';

const SIZE = 72;
let renderer: THREE.WebGLRenderer | null = null;
const queue: { design: string; img: HTMLImageElement; api: TemplatesApi }[] = [];
const cache = new Map<string, string>();
let busy = false;

function draw(parts: Awaited<ReturnType<TemplatesApi['mesh']>>['parts']): string {
  if (!renderer) {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true, canvas: document.createElement('canvas') });
    renderer.setPixelRatio(1); renderer.setClearColor(0xffffff);
  }
  renderer.setSize(SIZE, SIZE, false);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2); sun.position.set(1, -2, 3); scene.add(sun);
  const group = new THREE.Group();
  for (const p of parts) {
    const c = p.color;
    group.add(new THREE.Mesh(geometryOf(p.mesh), new THREE.MeshStandardMaterial({ color: new THREE.Color(c[0], c[1], c[2]), roughness: 0.8 })));
  }
  scene.add(group);
  const box = new THREE.Box3().setFromObject(group);
  const ctr = box.getCenter(new THREE.Vector3()), r = Math.max(1, box.getSize(new THREE.Vector3()).length() / 2);
  const cam = new THREE.PerspectiveCamera(35, 1, r / 100, r * 100);
  cam.up.set(0, 0, 1);
  cam.position.copy(ctr.clone().add(new THREE.Vector3(1, -1.6, 0.9).normalize().multiplyScalar(r / Math.sin((17.5 * Math.PI) / 180))));
  cam.lookAt(ctr);
  renderer.render(scene, cam);
  const url = renderer.domElement.toDataURL('image/png');
  group.traverse((o) => { if ((o as THREE.Mesh).geometry) (o as THREE.Mesh).geometry.dispose(); });
  return url;
}

async function pump(): Promise<void> {
  if (busy) return;
  busy = true;
  while (queue.length) {
    const { design, img, api } = queue.shift()!;
    try {
      if (!cache.has(design)) cache.set(design, draw((await api.mesh(design)).parts));
      img.src = cache.get(design)!; img.dataset.state = 'done';
    } catch { img.alt = 'no picture'; img.dataset.state = 'error'; }
  }
  busy = false;
}

/** Renders the design's thumbnail when the image scrolls into view. */
export function lazyThumbnail(api: TemplatesApi, design: string, img: HTMLImageElement): void {
  img.width = SIZE; img.height = SIZE; img.dataset.state = 'pending';
  if (cache.has(design)) { img.src = cache.get(design)!; img.dataset.state = 'done'; return; }
  const io = new IntersectionObserver((entries) => {
    if (entries.some((e) => e.isIntersecting)) { io.disconnect(); queue.push({ design, img, api }); void pump(); }
  });
  io.observe(img);
}
