// The hacks workspace (FabHacks): a WorkspaceModule for the shell.
import type { WorkspaceModule } from '../../shell/workspace';
import { emptyDesign } from './model';
import type { Design } from './model';
import { designToYaml, parseDesign } from './yamlio';
import { HacksWorkspace } from './workspace';

export const hacksWorkspace: WorkspaceModule<Design> = {
  kit: 'hacks',
  title: 'Hacks',
  summary: 'FabHacks: hang and hold things with off-the-shelf parts (hooks, clips, rods)',
  empty: emptyDesign,
  parse: parseDesign,
  serialize: designToYaml,
  nameOf: (d) => d.name,
  withName: (d, name) => ({ ...d, name }),
  mount: (ctx) => new HacksWorkspace(ctx),
};
