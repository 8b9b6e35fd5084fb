// The Flat-pack workspace (flat-pack furniture from planar pieces): a WorkspaceModule for the shell.
import type { WorkspaceModule } from '../../shell/workspace';
import { emptyDesign } from './model';
import type { FpDesign } from './model';
import { designToYaml, parseDesign } from './yamlio';
import { FlatpackWorkspace } from './workspace';
import './flatpack.css';

export const flatpackWorkspace: WorkspaceModule<FpDesign> = {
  kit: 'flatpack',
  title: 'Flat-pack',
  summary: 'Flat-pack furniture: planar pieces, joints cut for you, nested cut sheets',
  empty: emptyDesign,
  parse: parseDesign,
  serialize: designToYaml,
  nameOf: (d) => d.name,
  withName: (d, name) => ({ ...d, name }),
  mount: (ctx) => new FlatpackWorkspace(ctx),
};
