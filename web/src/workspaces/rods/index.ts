// The rods workspace (RodSteward): a WorkspaceModule for the shell.
import type { WorkspaceModule } from '../../shell/workspace';
import { emptyDesign } from './model';
import type { RodsDesign } from './model';
import { parseRodsYaml, rodsToYaml } from './yamlio';
import { RodsWorkspace } from './workspace';

export const rodsWorkspace: WorkspaceModule<RodsDesign> = {
  kit: 'rods',
  title: 'Rods',
  summary: 'RodSteward: rod-and-joint structures from 3D-printed joints and cut dowels',
  empty: emptyDesign,
  parse: parseRodsYaml,
  serialize: rodsToYaml,
  nameOf: (d) => d.name,
  withName: (d, name) => ({ ...d, name }),
  mount: (ctx) => new RodsWorkspace(ctx),
};
