// What the viewer costs the haptic loops: the demo run RUNS times without the viewer and RUNS
// times with it and a page open in headless Chromium (alternating, so drift of the host hits both
// alike); prints, per run and as mean, spread and range, the overruns and period p99 of
// local_contact's 1 kHz loop and the device bridge's 5 kHz loop, from summary.json.
// Run it alone on the machine (the services are real-time processes).
//   node bench/viewer/viewer_cost.mjs HAPTEX SCENE WORK_DIR [RUNS=4] [DURATION_S=20]

import { spawn } from "node:child_process";
import { mkdirSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { launchChromium, openViewer } from "../../web/tools/browser.mjs";

const [haptex, scene, work, runsText = "4", durationText = "20"] = process.argv.slice(2);
if (!haptex || !scene || !work) {
  console.error("usage: viewer_cost.mjs HAPTEX SCENE WORK_DIR [RUNS] [DURATION_S]");
  process.exit(2);
}
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
// the same scene without its viewer section
const withoutViewer = join(work, "no_viewer.textproto");
writeFileSync(withoutViewer, readFileSync(scene, "utf8").replace(/^viewer\s*\{[^}]*\}\s*$/m, "viewer { enabled: false }"));

function launch(scenePath, out, onUrl) {
  return new Promise((resolve, reject) => {
    const child = spawn(haptex, ["launch", scenePath, "--duration", durationText, "--out", out, "--viewer-port", "0",
                                 "--no-plots"], { stdio: ["ignore", "pipe", "pipe"] });
    let text = "";
    child.stdout.on("data", (d) => {
      text += d;
      const m = text.match(/viewer: open (http:\/\/[^ ]+\/)/);
      if (m && onUrl) { onUrl(m[1]); onUrl = null; }
    });
    child.on("exit", (code) => (code === 0 ? resolve() : reject(new Error(`launch exited ${code}:\n${text}`))));
  });
}

function loops(out) {
  const summary = JSON.parse(readFileSync(join(out, "summary.json"), "utf8"));
  const of = (name) => summary.services.find((s) => s.name === name).loops[0];
  return { local: of("local_contact"), bridge: of("device_bridge") };
}

const browser = await launchChromium();
const rows = { without: [], with: [] };
for (let i = 0; i < Number(runsText); ++i) {
  for (const kind of ["without", "with"]) {
    const out = join(work, `${kind}-${i}`);
    let page = null;
    await launch(kind === "with" ? scene : withoutViewer, out,
                 kind === "with" ? (url) => { openViewer(browser, url).then((p) => { page = p; }); } : null);
    if (kind === "with" && page === null) throw new Error("the page never showed the cloth");
    if (page) await page.close();
    const l = loops(out);
    rows[kind].push(l);
    console.log(`${kind.padEnd(7)} viewer run ${i}: local_contact overruns ${l.local.overruns}, period p99 ` +
                `${l.local.period_p99_us.toFixed(0)} us; bridge overruns ${l.bridge.overruns}, period p99 ` +
                `${l.bridge.period_p99_us.toFixed(0)} us`);
  }
}
await browser.close();

const describe = (values) => {
  const mean = values.reduce((a, b) => a + b, 0) / values.length;
  const sd = Math.sqrt(values.reduce((a, b) => a + (b - mean) ** 2, 0) / Math.max(1, values.length - 1));
  return `${mean.toFixed(1)} +- ${sd.toFixed(1)} (${Math.min(...values).toFixed(0)}-${Math.max(...values).toFixed(0)})`;
};
for (const kind of ["without", "with"]) {
  const r = rows[kind];
  console.log(`${kind} the viewer (${r.length} runs): local_contact overruns ${describe(r.map((x) => x.local.overruns))}, ` +
              `period p99 ${describe(r.map((x) => x.local.period_p99_us))} us; bridge overruns ` +
              `${describe(r.map((x) => x.bridge.overruns))}, period p99 ${describe(r.map((x) => x.bridge.period_p99_us))} us`);
}
