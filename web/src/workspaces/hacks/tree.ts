// The connection tree: parts as nodes, connections as labelled edges, laid out by dagre
// (layered, environment at the top; chosen over elkjs: 6 ms vs 41 ms for the reading nook's
// 22 parts and 20 connections, 52 kB vs 1.6 MB, both without crossings — docs/editor.md).
// Drawn at 1:1 in a scrolling box so labels keep their size; clicking a node selects the part,
// clicking an edge selects the connection.
import dagre from '@dagrejs/dagre';
import type { Design } from './model';
import { instances } from './model';

const NS = 'http://www.w3.org/2000/svg';
const NODE_H = 22, FONT_NODE = 11, FONT_EDGE = 10;

let measureCtx: CanvasRenderingContext2D | null = null;
/** Width of a text in px at a font size (the SVG uses the page's font). */
function textWidth(text: string, px: number): number {
  measureCtx ??= document.createElement('canvas').getContext('2d');
  if (!measureCtx) return text.length * px * 0.6;
  measureCtx.font = `${px}px system-ui, sans-serif`;
  return measureCtx.measureText(text).width;
}

/** "hook2 – rod1": the primitives of a connection (the nodes already name the parts). */
const shortLabel = (a: string, b: string) => `${a.split('.').slice(1).join('.')} – ${b.split('.').slice(1).join('.')}`;

export interface TreeSelection { node: string | null; edge: number | null }

export function renderTree(host: HTMLElement, d: Design, selected: TreeSelection, onNode: (name: string) => void, onEdge: (i: number) => void): void {
  host.innerHTML = '';
  const nodes = instances(d).map((i) => i.name);
  for (const e of d.environment) if (!nodes.includes(e.name)) nodes.unshift(e.name);
  if (!nodes.length) { host.textContent = 'No parts yet.'; return; }
  const edges = d.connections.map((c, i) => ({ a: c.a.split('.')[0], b: c.b.split('.')[0], full: `${c.a} – ${c.b}`, label: shortLabel(c.a, c.b), i }))
    .filter((e) => nodes.includes(e.a) && nodes.includes(e.b));
  // Orient every edge away from the environment (breadth-first depth), so the layers read top-down.
  const depth = new Map<string, number>();
  for (const e of d.environment) depth.set(e.name, 0);
  for (let changed = true; changed;) {
    changed = false;
    for (const e of edges) for (const [x, y] of [[e.a, e.b], [e.b, e.a]]) {
      if (depth.has(x) && !depth.has(y)) { depth.set(y, depth.get(x)! + 1); changed = true; }
    }
  }
  const g = new dagre.graphlib.Graph({ multigraph: true });
  g.setGraph({ rankdir: 'TB', nodesep: 16, ranksep: 28, edgesep: 8, marginx: 6, marginy: 6 });
  g.setDefaultEdgeLabel(() => ({}));
  for (const n of nodes) g.setNode(n, { width: textWidth(n, FONT_NODE) + 16, height: NODE_H });
  for (const e of edges) {
    const da = depth.get(e.a) ?? 1e9, db = depth.get(e.b) ?? 1e9;
    const [from, to] = da <= db ? [e.a, e.b] : [e.b, e.a];
    g.setEdge(from, to, { width: textWidth(e.label, FONT_EDGE) + 6, height: FONT_EDGE + 4, labelpos: 'c' }, String(e.i));
  }
  dagre.layout(g);
  const W = Math.ceil(g.graph().width ?? 100), H = Math.ceil(g.graph().height ?? 40);
  const svg = document.createElementNS(NS, 'svg');
  svg.setAttribute('width', String(W)); svg.setAttribute('height', String(H));
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
  svg.dataset.testid = 'tree-svg';
  const mk = (tag: string, attrs: Record<string, string | number>, text?: string) => {
    const e = document.createElementNS(NS, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
    if (text !== undefined) e.textContent = text;
    return e;
  };
  for (const e of g.edges()) {
    const info = edges[edges.findIndex((x) => String(x.i) === e.name)];
    const lab = g.edge(e) as { points: { x: number; y: number }[]; x: number; y: number };
    const pts = lab.points.map((p) => `${p.x.toFixed(1)},${p.y.toFixed(1)}`).join(' ');
    const group = mk('g', { class: 'tree-edge-group' + (selected.edge === info.i ? ' selected' : ''), 'data-testid': `tree-edge-group-${info.i}`, role: 'button', tabindex: 0, 'aria-label': `connection ${info.full}` });
    group.append(mk('title', {}, `connection ${info.full} (click to select)`),
      mk('polyline', { points: pts, class: 'tree-edge' }),
      mk('polyline', { points: pts, class: 'tree-edge-hit', 'data-testid': `tree-edge-hit-${info.i}` }),
      mk('text', { x: lab.x, y: lab.y + FONT_EDGE / 2 - 1, class: 'tree-edge-label', 'data-testid': `tree-edge-${info.i}`, 'data-connection': info.full }, info.label));
    group.addEventListener('click', () => onEdge(info.i));
    group.addEventListener('keydown', (ev) => { if ((ev as KeyboardEvent).key === 'Enter' || (ev as KeyboardEvent).key === ' ') { ev.preventDefault(); onEdge(info.i); } });
    svg.appendChild(group);
  }
  for (const n of nodes) {
    const p = g.node(n);
    const env = d.environment.some((e) => e.name === n), target = d.target?.name === n;
    const group = mk('g', { class: 'tree-node' + (n === selected.node ? ' selected' : '') + (env ? ' env' : '') + (target ? ' target' : ''), 'data-testid': `tree-node-${n}`, role: 'button', tabindex: 0, 'aria-label': `part ${n}` });
    group.append(mk('title', {}, `${n}${env ? ' (environment)' : target ? ' (target)' : ''} — click to select`),
      mk('rect', { x: p.x - p.width / 2, y: p.y - NODE_H / 2, width: p.width, height: NODE_H, rx: 6 }),
      mk('text', { x: p.x, y: p.y + 4 }, n));
    group.addEventListener('click', () => onNode(n));
    group.addEventListener('keydown', (ev) => { if ((ev as KeyboardEvent).key === 'Enter' || (ev as KeyboardEvent).key === ' ') { ev.preventDefault(); onNode(n); } });
    svg.appendChild(group);
  }
  host.appendChild(svg);
}
