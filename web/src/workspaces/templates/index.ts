// The templates workspace (design and fabrication by example): a WorkspaceModule for the shell.
import type { WorkspaceModule } from '../../shell/workspace';
import { emptyModel, modelToYaml, parseModel } from './model';
import type { TemplatesModel } from './model';
import { TemplatesWorkspace } from './workspace';

export const templatesWorkspace: WorkspaceModule<TemplatesModel> = {
  kit: 'templates',
  title: 'Templates',
  summary: 'Design and fabrication by example: compose furniture from parts of existing designs',
  empty: emptyModel,
  parse: parseModel,
  serialize: modelToYaml,
  nameOf: (d) => d.name,
  withName: (d, name) => ({ ...d, name }),
  mount: (ctx) => new TemplatesWorkspace(ctx),
};
