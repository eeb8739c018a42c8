// Headless Debian Chromium driven by puppeteer-core, for the viewer's browser test and the demo's
// screenshot. The flags keep Chromium off the network (this machine's is closed) and usable as root.

import puppeteer from "puppeteer-core";
import { mkdtempSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

export async function launchChromium() {
  return puppeteer.launch({
    executablePath: process.env.HAPTEX_CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    userDataDir: mkdtempSync(join(tmpdir(), "haptex-chromium-")),
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--window-size=1024,640"],
  });
}

/// Waits until the viewer at `url` serves its page (the launcher prints the address before the
/// viewer is up).
export async function waitUntilServed(url, timeoutMs = 30000) {
  const until = Date.now() + timeoutMs;
  for (;;) {
    try {
      if ((await fetch(new URL("/session.json", url))).ok) return;
    } catch (e) {
      if (Date.now() > until) throw new Error(`the viewer at ${url} never answered: ${e.message}`);
    }
    await new Promise((r) => setTimeout(r, 100));
  }
}

/// Opens the page at `url` and waits until it shows a cloth; returns the page.
export async function openViewer(browser, url, timeoutMs = 30000) {
  await waitUntilServed(url, timeoutMs);
  const page = await browser.newPage();
  await page.setViewport({ width: 1024, height: 640 });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  await page.goto(url, { waitUntil: "load" });
  await page.waitForFunction(() => window.haptexViewer && window.haptexViewer.stats.clothFrames > 0,
                             { timeout: timeoutMs, polling: 100 });
  page.haptexErrors = errors;
  return page;
}

export const stats = (page) => page.evaluate(() => JSON.parse(JSON.stringify(window.haptexViewer.stats)));
