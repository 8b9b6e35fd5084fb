// "Export Python": a FabHaL program in the paper's syntax (runnable with `fabkit run`).
import type { Design } from './model';
import type { Frame } from './api';

const n = (x: number) => String(Math.round(x * 1000) / 1000);
const frame = (f: Frame) => `Frame([${f.pos.map(n).join(',')}], [${f.rot.map(n).join(',')}])`;
const ident = (s: string) => s.replace(/[^A-Za-z0-9_]/g, '_').replace(/^([0-9])/, '_$1');

export function designToPython(d: Design): string {
  const L: string[] = ['from fabkit.hacks import *', '', `# ${d.name}`, 'assembly = Assembly()', ''];
  const call = (part: string, params?: Record<string, number>) =>
    `${part}(${Object.entries(params ?? {}).map(([k, v]) => `${k}=${n(v)}`).join(', ')})`;
  for (const e of d.environment) {
    if (e.part) L.push(`${ident(e.name)} = Environment({"part": ${call(e.part)}})`);
    else L.push(`# ${e.name}: loose primitives are not exported; use a library part`);
    L.push(`assembly.add(${ident(e.name)}, ${frame(e.frame)})`);
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
    const prim = d.target.primitive ? `  # frame of ${d.target.name}.${d.target.primitive}` : '';
    L.push(`assembly.end_with(${ident(d.target.name)}, ${frame(d.target.frame)})${prim}`);
  }
  L.push('');
  return L.join('\n');
}
