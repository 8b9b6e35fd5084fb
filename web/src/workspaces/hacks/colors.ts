// Colours of the eight primitive types, shared by the 3D view, the thumbnails and the legend.
export const PRIM_COLORS: Record<string, number> = {
  rod: 0x2f7dd1, hook: 0xe07b00, ring: 0x8e44ad, clip: 0x16a085, tube: 0x2c3e50,
  edge: 0x7f8c8d, surface: 0x95a5a6, hemisphere: 0xc0392b,
};
