// "Export Python": a FabHaL program in the paper's syntax (runnable with `fabkit run`).
import type { Design } from './model';
import type { Frame, Vec3 } from '../../shell/scene';
import * as THREE from 'three';
import { frameMatrix } from '../../shell/scene';

/** a ∘ b as a Frame (R = Rz·Ry·Rx, degrees). */
function compose(a: Frame, b: Frame): Frame {
  const m = frameMatrix(a).multiply(frameMatrix(b));
  const e = new THREE.Euler().setFromRotationMatrix(m, 'ZYX');
  const p = new THREE.Vector3().setFromMatrixPosition(m);
  const d = 180 / Math.PI;
  return { pos: [p.x, p.y, p.z], rot: [e.x * d, e.y * d, e.z * d] };
}
const specFrame = (f: any): Frame | null => {
  if (!f) return null;
  const fr: Frame = { pos: (f.pos ?? [0, 0, 0]).map(Number) as Vec3, rot: (f.rot ?? [0, 0, 0]).map(Number) as Vec3 };
  return [...fr.pos, ...fr.rot].some((x) => x !== 0) ? fr : null;
};

const n = (x: number) => String(Math.round(x * 1000) / 1000);
const frame = (f: Frame) => `Frame([${f.pos.map(n).join(',')}], [${f.rot.map(n).join(',')}])`;
const ident = (s: string) => s.replace(/[^A-Za-z0-9_]/g, '_').replace(/^([0-9])/, '_$1');

export function designToPython(d: Design): string {
  const L: string[] = ['from fabkit.hacks import *', '', `# ${d.name}`, 'assembly = Assembly()', ''];
  const dict = (o: Record<string, number>) => `{${Object.entries(o).map(([k, v]) => `"${k}": ${n(v)}`).join(', ')}}`;
  const call = (part: string, params?: Record<string, number>) =>
    `${part}(${params && Object.keys(params).length ? dict(params) : ''})`;
  // variable names of loose primitives: the primitive's name (as the paper does) unless it is taken
  const taken = new Set<string>([...d.environment.map((e) => ident(e.name)), ...d.parts.map((p) => ident(p.name)), 'assembly']);
  if (d.target) taken.add(ident(d.target.name));
  for (const e of d.environment) {
    let envFrame = e.frame;
    if (e.part) L.push(`${ident(e.name)} = Environment({"part": ${call(e.part)}})`);
    else {
      const entries: string[] = [];
      const prims = Object.entries(e.primitives ?? {});
      for (const [pname, raw] of prims) {
        const spec = { ...(raw as Record<string, unknown>) };
        const type = String(spec.type ?? '');
        let pf = specFrame(spec.frame);
        delete spec.type; delete spec.frame;
        // a single primitive's own frame folds into the environment's frame (same world placement)
        if (pf && prims.length === 1) { envFrame = compose(e.frame, pf); pf = null; }
        let v = ident(pname);
        if (taken.has(v)) v = `${ident(e.name)}_${v}`;
        taken.add(v);
        const sizes = Object.fromEntries(Object.entries(spec).map(([k, x]) => [k, Number(x)]));
        const cls = type.charAt(0).toUpperCase() + type.slice(1);
        if (pf) L.push(`# ${e.name}.${pname} has its own frame ${frame(pf)} inside ${e.name}, which FabHaL primitives cannot express; it is placed at ${e.name}'s frame here`);
        L.push(`${v} = ${cls}(${dict(sizes)})`);
        entries.push(`"${pname}": ${v}`);
      }
      L.push(`${ident(e.name)} = Environment({${entries.join(', ')}})`);
    }
    L.push(`assembly.add(${ident(e.name)}, ${frame(envFrame)})`);
  }
  L.push('');
  for (const p of d.parts) L.push(`${ident(p.name)} = ${call(p.part, p.params)}`);
  if (d.target && !d.parts.some((p) => p.name === d.target!.name)) L.push(`${ident(d.target.name)} = Environment({"part": ${call(d.target.part)}})`);
  L.push('');
  const ref = (r: string) => { const [i, p] = r.split('.'); return `${ident(i)}.${p}`; };
  for (const c of d.connections) {
    const opts = [c.alignment === 'flip' ? ', alignment="flip"' : '', c.fixed ? ', is_fixed=True' : ''].join('');
    L.push(`assembly.connect(${ref(c.a)}, ${ref(c.b)}${opts})`);
  }
  if (d.target) {
    // the goal is the frame of the target's primitive when the design names one (paper App. B.2: ENV_end.rod2)
    const what = d.target.primitive ? `${ident(d.target.name)}.${d.target.primitive}` : ident(d.target.name);
    L.push(`assembly.end_with(${what}, ${frame(d.target.frame)})`);
  }
  L.push('', 'result = assembly.solve()', 'print(result.summary())', 'print("stable", result.stable)', 'print(result)', '');
  return L.join('\n');
}
