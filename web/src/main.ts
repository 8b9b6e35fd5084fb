// The editor's entry point: the shell with every workspace this build has.
import './shell/style.css';
import { Shell } from './shell/shell';
import { workspaces } from './workspaces';

const shell = new Shell(workspaces);
shell.start().catch((e) => { shell.status(`error: ${(e as Error).message}`); });
