// One vocabulary for the hacks workspace: short default names, what the library's categories
// and the solver's terminations mean in words, units on sizes, and guidance where the library
// offers look-alike parts.

/** Parts whose default instance name is not their last word ("HookEyeConnector" → "eyehook"). */
const SHORT: Record<string, string> = {
  HookEyeConnector: 'eyehook', HookEyeLeft: 'eyehook', HookEyeLeftS: 'eyehook', HookEyeRight: 'eyehook',
  DoubleHook: 'shook', DoubleHookMedium: 'shook', ParamTurnbuckle: 'turnbuckle', ParamHanger: 'hanger',
};
const PRIMITIVE_WORDS = new Set(['rod', 'rods', 'hook', 'ring', 'clip', 'tube', 'edge', 'surface', 'hemisphere', 'env']);

/** A short base for new instance names: "RoundHandleBasket" → "basket", "ClosetRods" → "closetrods". */
export function shortName(part: string): string {
  if (SHORT[part]) return SHORT[part];
  const words = part.replace(/Env$/, '').match(/[A-Z]?[a-z0-9]+|[A-Z]+(?![a-z])/g) ?? [part];
  const last = words[words.length - 1].toLowerCase();
  // a last word that is also a primitive's name ("rod") would read as a primitive: keep two words
  const base = PRIMITIVE_WORDS.has(last) && words.length > 1 ? words.slice(-2).join('').toLowerCase() : last;
  return base.length >= 3 ? base : part.toLowerCase();
}

/** How the library's part categories read in the editor. */
export function categoryLabel(category: string): string {
  return ({ environment: 'environment or target (placed in the world)', hack: 'connector part', other: 'part', both: 'environment or part' } as Record<string, string>)[category] ?? category;
}

/** The solver's termination in words. */
export function terminationText(t: string): string {
  return ({
    CONVERGED: 'converged', NO_TARGET: 'no connected target: only relaxed under gravity',
    INFEASIBLE: 'the constraints could not be satisfied', MAX_ITERATIONS: 'stopped at the iteration limit (the result is still usable)',
    TIMEOUT: 'stopped at the time limit (the result is incomplete)', DID_NOT_CONVERGE: 'did not settle: the result is not a rest state',
  } as Record<string, string>)[t] ?? t.toLowerCase().replace(/_/g, ' ');
}

/** The solve's verdict in one or two words. The solver decides it (result.json's `verdict`,
 *  the line `fabkit solve` reports), so the editor never judges a result differently. */
export function verdictText(r: { verdict: string }): string {
  return ({
    STABLE: 'STABLE', PARTS_PASS_THROUGH: 'PARTS PASS THROUGH', INFEASIBLE: 'INFEASIBLE',
    STOPPED: 'STOPPED AT THE TIME LIMIT', FALLS_APART: 'FALLS APART', NOT_AT_REST: 'NOT AT REST',
  } as Record<string, string>)[r.verdict] ?? r.verdict.toLowerCase().replace(/_/g, ' ');
}

/** "arc angle 270°, arc radius 11.6 mm, wire radius 2 mm": a primitive's sizes with units. */
export function shapeSummary(shape: Record<string, number>): string {
  const name: Record<string, string> = { thickness: 'wire radius', arc_radius: 'arc radius', arc_angle: 'arc angle', inner_radius: 'inner radius', open_gap: 'opening', dist: 'jaw depth' };
  return Object.entries(shape).map(([k, v]) => `${name[k] ?? k.replace(/_/g, ' ')} ${+v.toFixed(2)}${k === 'arc_angle' ? '°' : ' mm'}`).join(', ');
}

/** Which of several look-alike parts to pick, where the library has such families. */
export function guidance(part: string): string | undefined {
  if (/^HookEye/.test(part)) {
    return 'Eye hooks differ only in how the hook is turned against the eye: HookEyeConnector (= HookEyeRight, hook at 90°, the paper\'s Task 1 part) is the usual choice; HookEyeLeft turns the hook to 120°; HookEyeLeftS (also HookEyeLeft5) has a flexible eye and a rigid hook, as in the user study.';
  }
  if (/^DoubleHook/.test(part)) return 'S-hooks: DoubleHook has a 9.6 mm opening, DoubleHookMedium 13.1 mm (for rods up to that radius).';
  return undefined;
}

/** What a primitive type is, in a few words (the paper's "hole" is the library's "ring"). */
export const PRIMITIVE_WORDS_DOC: Record<string, string> = {
  rod: 'a straight bar something can hang on', hook: 'an open wire arc that can catch a rod, ring or hook',
  ring: 'a closed loop (the paper calls it "hole")', clip: 'jaws that grip an edge or surface', tube: 'a hollow cylinder',
  edge: 'a thin flat edge a clip can grip', surface: 'a flat face something can rest on', hemisphere: 'a dome that can rest on a surface',
};
