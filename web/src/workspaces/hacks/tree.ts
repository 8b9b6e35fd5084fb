// Tree diagram of the connections: instances as nodes (environment at the top), connections as labelled edges.
import type { Design } from './model';
import { instances } from './model';

const NS = 'http://www.w3.org/2000/svg';

export function renderTree(host: HTMLElement, d: Design, selected: string | null, onSelect: (name: string) => void): void {
  host.innerHTML = '';
  const nodes = instances(d).map((i) => i.name);
  for (const e of d.environment) if (!nodes.includes(e.name)) nodes.unshift(e.name);
  const depth = new Map<string, number>();
  const roots = d.environment.map((e) => e.name);
  roots.forEach((r) => depth.set(r, 0));
  const edges = d.connections.map((c, i) => ({ a: c.a.split('.')[0], b: c.b.split('.')[0], label: `${c.a} – ${c.b}`, i }));
  for (let changed = true; changed;) {
    changed = false;
    for (const e of edges) for (const [x, y] of [[e.a, e.b], [e.b, e.a]]) {
      if (depth.has(x) && !depth.has(y)) { depth.set(y, depth.get(x)! + 1); changed = true; }
    }
  }
  const maxDepth = Math.max(0, ...depth.values());
  for (const n of nodes) if (!depth.has(n)) depth.set(n, maxDepth + 1);
  const rows = new Map<number, string[]>();
  for (const n of nodes) { const k = depth.get(n)!; rows.set(k, [...(rows.get(k) ?? []), n]); }
  const W = 440, rowH = 90;
  const pos = new Map<string, [number, number]>();
  for (const [k, names] of rows) names.forEach((n, i) => pos.set(n, [((i + 1) * W) / (names.length + 1), 24 + k * rowH]));
  const svg = document.createElementNS(NS, 'svg');
  const H = 48 + (Math.max(0, ...rows.keys())) * rowH;
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`); 
  svg.dataset.testid = 'tree-svg';
  edges.forEach((e) => {
    const p = pos.get(e.a), q = pos.get(e.b); if (!p || !q) return;
    const line = document.createElementNS(NS, 'line');
    line.setAttribute('x1', String(p[0])); line.setAttribute('y1', String(p[1])); line.setAttribute('x2', String(q[0])); line.setAttribute('y2', String(q[1]));
    line.setAttribute('class', 'tree-edge');
    svg.appendChild(line);
    const t = document.createElementNS(NS, 'text');
    const same = edges.filter((o) => (o.a === e.a && o.b === e.b) || (o.a === e.b && o.b === e.a)).indexOf(e);
    const mx = (p[0] + q[0]) / 2;
    // labels go to the outer side of the diagram so that edges meeting at one node do not overlap
    const anchor = Math.abs(mx - W / 2) < 1 ? 'middle' : mx < W / 2 ? 'end' : 'start';
    t.setAttribute('x', String(mx + (anchor === 'end' ? -4 : anchor === 'start' ? 4 : 0))); t.setAttribute('y', String((p[1] + q[1]) / 2 + 12 * same));
    t.setAttribute('text-anchor', anchor);
    t.setAttribute('class', 'tree-edge-label'); t.setAttribute('data-testid', `tree-edge-${e.i}`);
    t.textContent = e.label;
    svg.appendChild(t);
  });
  for (const n of nodes) {
    const [x, y] = pos.get(n)!;
    const g = document.createElementNS(NS, 'g');
    g.setAttribute('class', 'tree-node' + (n === selected ? ' selected' : ''));
    g.setAttribute('data-testid', `tree-node-${n}`);
    const r = document.createElementNS(NS, 'rect');
    r.setAttribute('x', String(x - 45)); r.setAttribute('y', String(y - 12)); r.setAttribute('width', '90'); r.setAttribute('height', '24'); r.setAttribute('rx', '6');
    const t = document.createElementNS(NS, 'text');
    t.setAttribute('x', String(x)); t.setAttribute('y', String(y + 4)); t.textContent = n;
    g.append(r, t);
    g.addEventListener('click', () => onSelect(n));
    svg.appendChild(g);
  }
  host.appendChild(svg);
}
