// The workspaces the editor has, one per kit. A new workspace is added here (docs/editor.md,
// "Adding a workspace"); the switcher offers it once the server also reports its kit.
import type { WorkspaceModule } from '../shell/workspace';
import { hacksWorkspace } from './hacks';

export const workspaces: WorkspaceModule[] = [hacksWorkspace];
