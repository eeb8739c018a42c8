// Headless Debian Chromium driven by puppeteer-core, for the viewer's browser test and the demo's
// screenshot. The flags keep Chromium off the network (this machine's is closed) and usable as root.

import puppeteer from "puppeteer-core";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

export async function launchChromium() {
  const profile = mkdtempSync(join(tmpdir(), "haptex-chromium-"));
  const browser = await puppeteer.launch({
    executablePath: process.env.HAPTEX_CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    userDataDir: profile,
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
           "--disable-component-update", "--disable-sync", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--window-size=1024,640"],
  });
  // the profile (some 40 MB) goes with the browser, once its process has exited and stopped writing it
  const close = browser.close.bind(browser);
  browser.close = async () => {
    await close();
    try {
      rmSync(profile, { recursive: true, force: true, maxRetries: 5, retryDelay: 100 });
    } catch (e) {
      console.error(`browser profile ${profile} left behind: ${e.message}`);
    }
  };
  return browser;
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

/// Opens the page at `url` and waits until it shows a cloth; returns the page. The wait is long:
/// beside a demo at normal scheduling on 2 cores a browser takes 10-30 s to load the page.
export async function openViewer(browser, url, timeoutMs = 60000) {
  await waitUntilServed(url, timeoutMs);
  const page = await browser.newPage();
  await page.setViewport({ width: 1024, height: 640 });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  await page.goto(url, { waitUntil: "load" });
  try {
    await page.waitForFunction(() => window.haptexViewer && window.haptexViewer.stats.clothFrames > 0,
                               { timeout: timeoutMs, polling: 100 });
  } catch (e) {
    // say what the page did get, so a failure shows whether it loaded, connected or decoded
    const shown = await page.evaluate(() => {
      const s = window.haptexViewer?.stats;
      return s ? JSON.stringify({ status: s.status, messages: s.messages, clothFrames: s.clothFrames, errors: s.errors })
               : "no window.haptexViewer";
    }).catch((why) => `not readable: ${why}`);
    throw new Error(`the page at ${url} showed no cloth within ${timeoutMs} ms (${e.message}): ${shown}; ` +
                    `page errors: ${errors.join("; ") || "none"}`);
  }
  page.haptexErrors = errors;
  return page;
}

export const stats = (page) => page.evaluate(() => JSON.parse(JSON.stringify(window.haptexViewer.stats)));

/// The page's drawing over up to `seconds` one-second windows, ended early once `going()` is false
/// (a live run that has ended): its frame rate { best, median } over the windows, how many windows,
/// and how many frames it drew and cloth frames it took in meanwhile.
export async function frameRate(page, seconds, going = () => true) {
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  const first = await stats(page);
  const samples = [];
  for (let i = 0; i < seconds; ++i) {
    await sleep(1000);
    if (!going()) break;
    samples.push((await stats(page)).fps);
  }
  const last = await stats(page);
  samples.sort((x, y) => x - y);
  return { best: samples.length ? samples[samples.length - 1] : NaN,
           median: samples.length ? samples[Math.floor(samples.length / 2)] : NaN, windows: samples.length,
           framesDrawn: last.framesRendered - first.framesRendered, clothFramesTaken: last.clothFrames - first.clothFrames };
}
