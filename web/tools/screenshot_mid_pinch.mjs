// The demo's picture of the fabric mid-pinch: opens the replay page of a finished run at URL
// (`haptex view RUN`), moves its timeline to the first moment both fingers pinch the cloth
// (contact state VIII or IX) and saves a screenshot to OUT.
//   node web/tools/screenshot_mid_pinch.mjs URL OUT

import { launchChromium, openViewer } from "./browser.mjs";

const [url, out] = process.argv.slice(2);
if (!url || !out) {
  console.error("usage: screenshot_mid_pinch.mjs URL OUT");
  process.exit(2);
}
const browser = await launchChromium();
try {
  const page = await openViewer(browser, url);
  const t = await page.evaluate(() => window.haptexViewer.seekToPinch());
  if (t < 0) throw new Error("the run has no moment where both fingers pinch");
  await new Promise((r) => setTimeout(r, 300));  // a few frames at that moment
  await page.screenshot({ path: out });
  console.log(`viewer screenshot mid-pinch (t = ${t.toFixed(2)} s of the run): ${out}`);
} catch (e) {
  console.error(`viewer screenshot failed: ${e.message}`);
  process.exitCode = 1;
} finally {
  await browser.close();
}
