// Validates .glb files with the Khronos glTF validator; exits 1 on any error or warning.
// Usage: node check-glb.mjs FILE.glb [...]
import { validateBytes } from 'gltf-validator';
import { readFileSync } from 'fs';

let failed = false;
for (const file of process.argv.slice(2)) {
  const report = await validateBytes(new Uint8Array(readFileSync(file)));
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings`);
  for (const m of messages) {
    if (m.severity <= 1) console.log(`  ${m.code} at ${m.pointer}: ${m.message}`);
  }
  if (numErrors > 0 || numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);
