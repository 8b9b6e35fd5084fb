// The guided assembly (RodSteward §5, RSAssembler): step through the library's depth-first
// order. The current part in full colour, placed parts recessed toward the background, future
// parts as faint dots (joints) and lines (rods); the camera eases to the current part with its
// neighbours; joints carry their engraved ID, rods their length. Also the printable guide: one
// small picture and one line per step.
import * as THREE from 'three';
import { geometryOf, outlineMaterial } from '../../shell/scene';
import { el, download } from '../../shell/ui';
import { fileStem } from '../../shell/shell';
import type { AssemblyStep, Preview } from './api';
import type { RodsWorkspace } from './workspace';
import { JOINT_COLOR, ROD_COLOR } from './workspace';

const BACKGROUND = 0xf4f6f8;
const DESIGN_LAYERS = ['rods-joints', 'rods-rods', 'rods-checks', 'rods-skeleton', 'rods-free'];

/** The current part's outline (orange, constant screen width): it stands out on any background. */
function outline(mesh: THREE.Mesh, resolution: THREE.Vector2): THREE.Mesh {
  const m = outlineMaterial(0xff9800, 3);
  m.uniforms.resolution.value.copy(resolution);
  const hull = new THREE.Mesh(mesh.geometry, m);
  hull.raycast = () => {};
  return hull;
}

export class Assembler {
  active = false;
  step = 0;
  /** The preview the steps are of (frozen while assembling). */
  private p: Preview | null = null;
  private kept: number[] = [];

  constructor(private w: RodsWorkspace) {}

  get steps(): AssemblyStep[] { return this.p?.assembly ?? []; }

  start(): void {
    const w = this.w;
    if (!w.preview || w.previewError) { w.ctx.message('Nothing to assemble yet: the design needs joints and rods the library can make.', 'info'); return; }
    this.p = w.preview; this.kept = [...w.kept];
    this.active = true; this.step = 0;
    w.transform.detach();
    w.ctx.scene.clearLayer('rods-checks'); // its labels are HTML: hiding the layer would leave them
    w.ctx.scene.clearLayer('rods-numbers');
    for (const l of DESIGN_LAYERS) w.ctx.scene.layer(l).visible = false;
    this.redraw();
    this.ease(0);
    this.renderPanel();
  }

  stop(): void {
    if (!this.active) { this.renderPanel(); return; }
    this.active = false;
    const scene = this.w.ctx.scene;
    scene.clearLayer('rods-assembly');
    for (const l of DESIGN_LAYERS) scene.layer(l).visible = true;
    this.w.draw();
    this.renderPanel();
  }

  next(): void { if (this.active && this.step < this.steps.length - 1) { this.step++; this.redraw(); this.ease(500); this.renderPanel(); } }
  back(): void { if (this.active && this.step > 0) { this.step--; this.redraw(); this.ease(500); this.renderPanel(); } }

  state() {
    const s = this.steps[this.step];
    return { active: this.active, step: this.step, count: this.steps.length, text: s?.text ?? '', kind: s?.kind ?? null, camera: this.w.ctx.scene.controls.target.toArray() };
  }

  /** Which joints and rods are placed before step k, and the part of step k. */
  private partsAt(k: number) {
    const placedJoints = new Set<number>(), placedRods = new Set<number>();
    this.steps.slice(0, k).forEach((s) => { if (s.kind === 'joint') placedJoints.add(s.joint!); else placedRods.add(s.rod!); });
    return { placedJoints, placedRods, current: this.steps[k] };
  }

  /** The scene of step k: current part full colour, placed parts recessed, future parts faint. */
  private group(k: number, resolution: THREE.Vector2): THREE.Group {
    const p = this.p!;
    const g = new THREE.Group();
    const { placedJoints, placedRods, current } = this.partsAt(k);
    const recessed = (c: number) => new THREE.MeshStandardMaterial({ color: new THREE.Color(c).lerp(new THREE.Color(BACKGROUND), 0.55), transparent: true, opacity: 0.55, roughness: 0.9, flatShading: true, depthWrite: false });
    const full = (c: number) => new THREE.MeshStandardMaterial({ color: c, roughness: 0.6, flatShading: true, emissive: 0x221100 });
    const futurePoints: number[] = [];
    const futureLines: number[] = [];
    p.joints.forEach((j, i) => {
      const isCurrent = current?.kind === 'joint' && current.joint === i;
      if (isCurrent || placedJoints.has(i)) {
        const m = new THREE.Mesh(geometryOf(j.mesh), isCurrent ? full(JOINT_COLOR) : recessed(JOINT_COLOR));
        m.name = isCurrent ? 'current' : 'placed';
        if (isCurrent) m.add(outline(m, resolution));
        g.add(m);
      } else futurePoints.push(...j.position);
    });
    p.rods.forEach((r, e) => {
      const isCurrent = current?.kind === 'rod' && current.rod === e;
      if (isCurrent || placedRods.has(e)) {
        const m = new THREE.Mesh(geometryOf(r.mesh), isCurrent ? full(ROD_COLOR) : recessed(ROD_COLOR));
        m.name = isCurrent ? 'current' : 'placed';
        if (isCurrent) m.add(outline(m, resolution));
        g.add(m);
      } else futureLines.push(...p.joints[r.a].position, ...p.joints[r.b].position);
    });
    if (futurePoints.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.Float32BufferAttribute(futurePoints, 3));
      const pts = new THREE.Points(geo, new THREE.PointsMaterial({ color: 0x7d8893, size: 8, sizeAttenuation: false, transparent: true, opacity: 0.7 }));
      pts.name = 'future-joints';
      g.add(pts);
    }
    if (futureLines.length) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.Float32BufferAttribute(futureLines, 3));
      const lines = new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color: 0xaab3bb, transparent: true, opacity: 0.5 }));
      lines.name = 'future-rods';
      g.add(lines);
    }
    return g;
  }

  /** The current part and its neighbours (joints next to it): what the camera keeps in view. */
  private focusBox(k: number): THREE.Box3 {
    const p = this.p!;
    const s = this.steps[k];
    const box = new THREE.Box3();
    const addJoint = (i: number) => { const m = p.joints[i].mesh.vertices; for (let v = 0; v < m.length; v += 3) box.expandByPoint(new THREE.Vector3(m[v], m[v + 1], m[v + 2])); };
    if (!s) return box;
    if (s.kind === 'joint') {
      addJoint(s.joint!);
      for (const e of p.joints[s.joint!].rods) { const r = p.rods[e]; addJoint(r.a === s.joint ? r.b : r.a); }
    } else { addJoint(s.from!); addJoint(s.to!); }
    return box;
  }

  redraw(): void {
    if (!this.active || !this.p) return;
    const scene = this.w.ctx.scene;
    scene.clearLayer('rods-assembly');
    const layer = scene.layer('rods-assembly');
    layer.add(this.group(this.step, scene.renderer.getSize(new THREE.Vector2())));
    const p = this.p;
    const { placedJoints, current } = this.partsAt(this.step);
    for (const i of placedJoints) scene.addLabel('rods-assembly', new THREE.Vector3(...p.joints[i].position), p.joints[i].label, { class: 'rods-id', 'data-testid': `assembly-label-${p.joints[i].label}` });
    if (current?.kind === 'joint') {
      const j = p.joints[current.joint!];
      scene.addLabel('rods-assembly', new THREE.Vector3(...j.position), j.label, { class: 'rods-id big', 'data-testid': 'assembly-current-label' });
    } else if (current?.kind === 'rod') {
      const r = p.rods[current.rod!];
      const a = new THREE.Vector3(...p.joints[r.a].position), b = new THREE.Vector3(...p.joints[r.b].position);
      scene.addLabel('rods-assembly', a.add(b).multiplyScalar(0.5), `${r.name.replace('rod ', '')} · ${r.length.toFixed(1)} mm`, { class: 'rods-length', 'data-testid': 'assembly-current-label' });
    }
    scene.render();
  }

  /** Eases the camera so the current part and its neighbours are centred and in view. */
  private ease(ms: number): void {
    const scene = this.w.ctx.scene;
    const box = this.focusBox(this.step);
    if (box.isEmpty()) return;
    const c = box.getCenter(new THREE.Vector3());
    const size = Math.max(60, box.getSize(new THREE.Vector3()).length());
    const cam = scene.camera;
    const t0 = scene.controls.target.clone(), p0 = cam.position.clone();
    const dir = p0.clone().sub(t0).normalize();
    let p1: THREE.Vector3;
    if (cam === scene.perspective) p1 = c.clone().add(dir.multiplyScalar((size / (2 * Math.tan((scene.perspective.fov * Math.PI) / 360))) * 1.3));
    else p1 = c.clone().add(p0.clone().sub(t0));
    const zoom0 = cam.zoom;
    const zoom1 = cam === scene.orthographic ? Math.max(0.05, (scene.orthographic.top - scene.orthographic.bottom) / (size * 1.3)) : 1;
    void scene.animate(ms, (t) => {
      const s = t * t * (3 - 2 * t); // smoothstep: starts and ends gently
      scene.controls.target.lerpVectors(t0, c, s);
      cam.position.lerpVectors(p0, p1, s);
      cam.zoom = zoom0 + (zoom1 - zoom0) * s;
      cam.updateProjectionMatrix();
      scene.controls.update();
    });
  }

  renderPanel(): void {
    const b = this.w.panels?.assembly;
    if (!b) return;
    b.innerHTML = '';
    if (!this.active) {
      const go = el('button', { 'data-testid': 'assemble-start', title: 'Step through the assembly: one joint or rod at a time' }, 'Start assembly');
      go.addEventListener('click', () => this.start());
      const n = this.w.preview?.assembly.length ?? 0;
      b.append(go, el('span', { class: 'hint' }, n ? ` ${n} steps` : ''));
      return;
    }
    const s = this.steps[this.step];
    const back = el('button', { 'data-testid': 'assemble-back', title: 'Previous step (←)' }, '← Back') as HTMLButtonElement;
    const next = el('button', { 'data-testid': 'assemble-next', title: 'Next step (→)', class: 'primary' }, 'Next →') as HTMLButtonElement;
    const stop = el('button', { 'data-testid': 'assemble-stop', title: 'Back to designing (Esc)' }, 'Done');
    back.disabled = this.step === 0; next.disabled = this.step >= this.steps.length - 1;
    back.addEventListener('click', () => this.back());
    next.addEventListener('click', () => this.next());
    stop.addEventListener('click', () => this.stop());
    b.append(el('div', { class: 'row' }, back, next, stop),
      el('div', { 'data-testid': 'assemble-step', class: 'assembly-step' }, el('b', {}, `Step ${this.step + 1} of ${this.steps.length}: `), s?.text ?? ''));
  }

  // ---------------------------------------------------------------- the printable guide
  /** One small picture per step, rendered offscreen with the same focus+context look. */
  private async pictures(width = 220, height = 165): Promise<string[]> {
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(1);
    renderer.setSize(width, height, false);
    renderer.setClearColor(0xffffff);
    const camera = new THREE.PerspectiveCamera(40, width / height, 1, 50000);
    camera.up.set(0, 0, 1);
    const out: string[] = [];
    try {
      for (let k = 0; k < this.steps.length; ++k) {
        const scene = new THREE.Scene();
        scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
        const sun = new THREE.DirectionalLight(0xffffff, 1.2); sun.position.set(1, -2, 3); scene.add(sun);
        const g = this.group(k, new THREE.Vector2(width, height));
        scene.add(g);
        const whole = new THREE.Box3().setFromObject(g);
        // the current part and its neighbours, with some of the rest around them
        const focus = this.focusBox(k);
        const c = focus.getCenter(new THREE.Vector3());
        const size = Math.min(whole.getSize(new THREE.Vector3()).length(), Math.max(60, focus.getSize(new THREE.Vector3()).length() * 1.4));
        camera.position.copy(c.clone().add(new THREE.Vector3(1, -1.3, 0.9).normalize().multiplyScalar((size / (2 * Math.tan((40 * Math.PI) / 360))) * 1.1)));
        camera.lookAt(c);
        renderer.render(scene, camera);
        out.push(renderer.domElement.toDataURL('image/png'));
        g.traverse((o) => { const m = o as THREE.Mesh; if (m.geometry) m.geometry.dispose(); });
        if (k % 4 === 3) await new Promise((r) => setTimeout(r, 0));
      }
    } finally { renderer.dispose(); renderer.forceContextLoss(); }
    return out;
  }

  async guideHtml(): Promise<string> {
    const w = this.w;
    if (!this.p || !this.active) { this.p = w.preview; this.kept = [...w.kept]; }
    const p = this.p;
    if (!p) return '';
    const pics = await this.pictures();
    const esc = (s: string) => s.replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]!));
    const d = w.ctx.history.current;
    const rows = this.steps.map((s, k) => `<li class="step"><img src="${pics[k]}" width="220" height="165" alt="step ${k + 1}"><span><b>${k + 1}.</b> ${esc(s.text)}</span></li>`).join('\n');
    return `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>${esc(d.name)}: assembly guide</title>
<style>
body { font: 13px/1.35 system-ui, sans-serif; margin: 16px; color: #222; }
h1 { font-size: 18px; margin: 0 0 4px; } p { margin: 2px 0 10px; color: #555; }
ol { list-style: none; padding: 0; display: grid; grid-template-columns: repeat(auto-fill, minmax(230px, 1fr)); gap: 10px; }
li.step { break-inside: avoid; border: 1px solid #ccd; border-radius: 4px; padding: 4px; }
li.step img { display: block; width: 100%; height: auto; } li.step span { display: block; margin-top: 3px; }
@media print { button { display: none; } body { margin: 6mm; } }
</style></head><body>
<h1>${esc(d.name)}: assembly guide</h1>
<p>${p.joints.length} joints and ${p.rods.length} rods (${esc(`2r = ${(2 * p.parameters.radius).toFixed(2)} mm`)}); ${this.steps.length} steps, depth-first. Each joint carries its number; cut each rod to the length given. Current part in colour, placed parts faded, parts still to come as dots and lines.</p>
<button onclick="print()">Print</button>
<ol data-steps="${this.steps.length}">
${rows}
</ol>
</body></html>
`;
  }

  async openGuide(): Promise<void> {
    const html = await this.guideHtml();
    const url = URL.createObjectURL(new Blob([html], { type: 'text/html' }));
    const win = window.open(url, '_blank');
    if (!win) this.w.ctx.message('The browser blocked the guide\'s window: use Download guide (HTML) and open the file.', 'info');
  }

  async downloadGuide(): Promise<void> {
    download(`${fileStem(this.w.ctx.history.current.name)}_assembly_guide.html`, await this.guideHtml(), 'text/html');
  }
}
