// Small DOM helpers shared by the panels.
import type { Frame, Vec3 } from './scene';

export function el(tag: string, attrs: Record<string, string> = {}, ...children: (Node | string)[]): HTMLElement {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'value') (e as HTMLInputElement).value = v;
    else e.setAttribute(k, v);
  }
  e.append(...children);
  return e;
}

export function download(name: string, data: string | Blob, type: string): void {
  const blob = typeof data === 'string' ? new Blob([data], { type }) : data;
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob); a.download = name;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

/** Position (mm) and rotation (degrees) sliders plus numeric fields; `onCommit` runs on change. */
export function frameEditor(id: string, title: string, frame: Frame, onRename: (n: string) => void, name: string,
                            onCommit: (f: Frame) => void, onDelete: () => void): HTMLElement {
  const box = el('div', { class: 'frame-editor', 'data-testid': `frame-${id}` });
  const nameInput = el('input', { value: name, 'data-testid': `frame-${id}-name`, style: 'width:110px' }) as HTMLInputElement;
  nameInput.addEventListener('change', () => { if (nameInput.value.trim() && nameInput.value !== name) onRename(nameInput.value.trim()); });
  const del = el('button', { 'data-testid': `frame-${id}-delete`, title: `Delete ${name} and its connections (undoable)` }, 'delete');
  del.addEventListener('click', onDelete);
  box.append(el('div', {}, el('b', {}, title)), el('div', {}, 'name ', nameInput, ' ', del));
  const f: Frame = { pos: [...frame.pos] as Vec3, rot: [...frame.rot] as Vec3 };
  const rows: [keyof Frame, number, string, number, number][] = [
    ['pos', 0, 'x', -2000, 2000], ['pos', 1, 'y', -2000, 2000], ['pos', 2, 'z', -2000, 2000],
    ['rot', 0, 'rx', -180, 180], ['rot', 1, 'ry', -180, 180], ['rot', 2, 'rz', -180, 180],
  ];
  for (const [k, i, label, min, max] of rows) {
    const unit = k === 'pos' ? 'mm' : '°';
    const slider = el('input', { type: 'range', min: String(min), max: String(max), step: k === 'pos' ? '1' : '0.5', value: String(f[k][i]), 'data-testid': `frame-${id}-${label}-slider` }) as HTMLInputElement;
    const field = el('input', { type: 'number', step: 'any', value: String(+f[k][i].toFixed(4)), 'data-testid': `frame-${id}-${label}`, title: unit }) as HTMLInputElement;
    slider.addEventListener('input', () => { field.value = slider.value; });
    slider.addEventListener('change', () => { f[k][i] = Number(slider.value); onCommit(f); });
    field.addEventListener('change', () => { const v = Number(field.value); if (Number.isFinite(v)) { f[k][i] = v; onCommit(f); } });
    box.append(el('div', { class: 'frame-row' }, el('span', {}, `${label} ${unit}`), slider, field));
  }
  return box;
}
