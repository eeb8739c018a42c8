// The demo's picture of the fabric mid-pinch: opens the live viewer at URL, waits until both
// fingers pinch the cloth (contact state VIII or IX), and saves a screenshot to OUT.
//   node web/tools/screenshot_mid_pinch.mjs URL OUT [TIMEOUT_S]

import { launchChromium, openViewer } from "./browser.mjs";

const [url, out, timeoutS = "40"] = process.argv.slice(2);
if (!url || !out) {
  console.error("usage: screenshot_mid_pinch.mjs URL OUT [TIMEOUT_S]");
  process.exit(2);
}
const browser = await launchChromium();
try {
  const page = await openViewer(browser, url, Number(timeoutS) * 1000);
  const pinched = (s) => ["VIII", "IX"].includes(s.contactStates.thumb) && ["VIII", "IX"].includes(s.contactStates.index);
  await page.waitForFunction(
    (p) => {
      const s = window.haptexViewer.stats;
      return p.includes(s.contactStates.thumb) && p.includes(s.contactStates.index);
    },
    { timeout: Number(timeoutS) * 1000, polling: 50 }, ["VIII", "IX"]);
  await new Promise((r) => setTimeout(r, 300));  // a few frames of the pinch
  await page.screenshot({ path: out });
  const s = await page.evaluate(() => window.haptexViewer.stats);
  console.log(`viewer screenshot mid-pinch: ${out} (thumb ${s.contactStates.thumb}, index ${s.contactStates.index}, ` +
              `${s.fps.toFixed(0)} frames/s, pinched ${pinched(s)})`);
} catch (e) {
  console.error(`viewer screenshot failed: ${e.message}`);
  process.exitCode = 1;
} finally {
  await browser.close();
}
