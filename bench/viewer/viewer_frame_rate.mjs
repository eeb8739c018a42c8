// How fast the viewer's page draws in headless Chromium on this host: RUNS demo runs, each live
// under normal scheduling (--rt-priority 0, where a browser on the same cores gets its share), live
// under the launcher's real-time scheduling, and replayed by `haptex view`; prints, per run and
// over all, the best and median frame rate of one-second windows (live: only windows within the
// run) and the render scale the page settled on. Run it alone on the machine: the figure is the host's as much as the page's.
//   node bench/viewer/viewer_frame_rate.mjs HAPTEX SCENE WORK_DIR [RUNS=3] [WINDOW_S=8]

import { mkdirSync, rmSync } from "node:fs";
import { join } from "node:path";
import { frameRate, launchChromium, openViewer, stats } from "../../web/tools/browser.mjs";
import { startHaptex } from "../../web/tools/haptex_process.mjs";

const [haptex, scene, work, runsText = "3", windowText = "8"] = process.argv.slice(2);
if (!haptex || !scene || !work) {
  console.error("usage: viewer_frame_rate.mjs HAPTEX SCENE WORK_DIR [RUNS] [WINDOW_S]");
  process.exit(2);
}
const windowS = Number(windowText);
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const start = (args, urlPattern) => startHaptex(haptex, args, urlPattern);

// the page's frame rate over the window, after the first seconds in which it settles its render scale
async function measure(browser, url, going) {
  const page = await openViewer(browser, url);
  await sleep(2000);
  const rate = await frameRate(page, windowS, going);
  const { renderScale } = await stats(page);
  await page.close();
  return { ...rate, renderScale };
}

async function live(browser, out, extraArgs) {
  const run = start(["launch", scene, "--duration", "30", "--out", out, "--viewer-port", "0", "--no-plots", ...extraArgs],
                    /viewer: open (http:\/\/[^ ]+\/)/);
  const rate = await measure(browser, await run.url, run.going);
  if (rate.windows === 0) throw new Error(`the page in ${out} loaded too late to measure: use a longer run`);
  const { code } = await run.exited;
  if (code !== 0) throw new Error(`the run in ${out} exited ${code}:\n${run.output()}`);
  return rate;
}

async function replay(browser, runDir) {
  const view = start(["view", runDir, "--port", "0", "--seconds", "120"], /on (http:\/\/[^ ]+\/)/);
  const rate = await measure(browser, await view.url, view.going);
  view.child.kill("SIGINT");
  await view.exited;
  return rate;
}

const browser = await launchChromium();
const rows = { "live, normal scheduling": [], "live, real-time scheduling": [], replay: [] };
const show = (r) => `best ${r.best.toFixed(1)}, median ${r.median.toFixed(1)} frames/s over ${r.windows} windows ` +
                   `(render scale ${r.renderScale.toFixed(2)})`;
try {
  for (let i = 0; i < Number(runsText); ++i) {
    const normalDir = join(work, `normal-${i}`);
    const measured = {
      "live, normal scheduling": await live(browser, normalDir, ["--rt-priority", "0"]),
      "live, real-time scheduling": await live(browser, join(work, `realtime-${i}`), []),
      replay: await replay(browser, normalDir),
    };
    for (const [kind, r] of Object.entries(measured)) {
      rows[kind].push(r);
      console.log(`run ${i}, ${kind}: ${show(r)}`);
    }
  }
} finally {
  await browser.close();
}
const range = (values) => `${Math.min(...values).toFixed(1)}-${Math.max(...values).toFixed(1)}`;
for (const [kind, r] of Object.entries(rows)) {
  console.log(`${kind} (${r.length} runs, ${windowS} s windows): best ${range(r.map((x) => x.best))}, ` +
              `median ${range(r.map((x) => x.median))} frames/s`);
}
