// `haptex` as a child process that serves the viewer (`launch ... --viewer-port 0`, `view`), for
// the browser test and the viewer's benchmarks.

import { spawn } from "node:child_process";

/// Starts `haptex ARGS`. Returns { child, url, exited, output, going }: `url` resolves to the page's
/// address once its line matching `urlPattern` (first group) is printed, and rejects if haptex
/// exits first; `exited` resolves to { code, signal }; `going()` is true until it exits.
export function startHaptex(haptex, args, urlPattern) {
  const child = spawn(haptex, args, { stdio: ["ignore", "pipe", "pipe"] });
  let out = "", running = true;
  const exited = new Promise((resolve) => child.on("exit", (code, signal) => {
    running = false;
    resolve({ code, signal });
  }));
  const url = new Promise((resolve, reject) => {
    child.stdout.on("data", (d) => {
      out += d;
      const m = out.match(urlPattern);
      if (m) resolve(m[1]);
    });
    child.stderr.on("data", (d) => { out += d; });
    child.on("exit", (code) => reject(new Error(`haptex ${args[0]} exited (${code}) before serving the page:\n${out}`)));
  });
  return { child, url, exited, output: () => out, going: () => running };
}
