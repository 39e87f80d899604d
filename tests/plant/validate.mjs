// Validates the power plant of `hlodr plant` with the Khronos glTF-Validator (npm gltf-validator,
// kept in vendor/ and installed offline by scripts/test.sh): no errors and no warnings.
//   node validate.mjs [FILE.glb]   validates FILE, or writes a small plant with $HLODR_BINARY
// Exit status 77 (ctest's skip) when the validator module is not installed.
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

let validator;
try {
  validator = await import("gltf-validator");
} catch {
  console.log("plant.gltf: gltf-validator is not installed (npm ci --offline in tests/plant)");
  process.exit(process.env.CI ? 1 : 77);
}

let file = process.argv[2];
let dir;
if (!file) {
  dir = mkdtempSync(join(tmpdir(), "hlodr-plant-"));
  execFileSync(process.env.HLODR_BINARY ?? "hlodr",
                         ["plant", "-o", dir, "--objects", "1", "--detail", "0.5"], { stdio: "inherit" });
  file = join(dir, "plant.glb");
}
try {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    maxIssues: 50,
  });
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ` +
              `${numHints} hints (glTF-Validator ${report.validatorVersion})`);
  for (const m of messages.slice(0, 20)) console.log(`  ${m.severity} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  const info = report.info ?? {};
  console.log(`  ${info.totalTriangleCount} triangles, ${info.drawCallCount} draw calls, ` +
              `${info.materialCount} materials`);
  const ok = numErrors === 0 && numWarnings === 0;
  process.exit(ok ? 0 : 1);
} finally {
  if (dir) rmSync(dir, { recursive: true, force: true });
}
