// What the tuning page's browser tests share (drive.mjs, servo.mjs, bode.mjs): the command
// line, Debian's headless Chromium in a throwaway profile, the page's errors and any request
// that leaves the server, a 50 s limit on the whole run, and the one JSON line printed.
//
// `run(name, defaults, body, launch)`: `body({ page, opt, base, url, ctx })` returns what the
// script read; it is printed as JSON with `page_errors`, `console_errors` and
// `foreign_requests` added. `launch` adds `viewport` and Chromium `args`. Exits 1 with the
// reason on stderr when a step fails or the run takes longer than 50 s; 2 without a URL.
// CHROMIUM names the browser (default /usr/bin/chromium).
import { chromium } from "playwright-core";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

export async function run(name, defaults, body, launch = {}) {
  const [url, argJson] = process.argv.slice(2);
  if (!url) {
    console.error(`usage: node ${name} URL [JSON options]`);
    process.exit(2);
  }
  const opt = { ...defaults, ...JSON.parse(argJson || "{}") };
  // The server's own address, without the token (the page's requests all start with it).
  const base = new URL(url);
  base.hash = "";
  const deadline = setTimeout(() => {
    console.error(`${name}: the page did not finish within 50 s`);
    process.exit(1);
  }, 50000);
  const profile = mkdtempSync(join(tmpdir(), "tuning-chromium-"));
  let ctx;
  try {
    ctx = await chromium.launchPersistentContext(profile, {
      executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
      headless: true,
      viewport: launch.viewport || { width: 1280, height: 1400 },
      args: ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        ...(launch.args || [])],
    });
    const page = ctx.pages()[0] || (await ctx.newPage());
    // Exceptions in the page's scripts, and the console's errors (a refused request logs one).
    const pageErrors = [];
    const consoleErrors = [];
    page.on("pageerror", (e) => pageErrors.push(String(e)));
    page.on("console", (m) => {
      if (m.type() === "error") consoleErrors.push(m.text());
    });
    // The page must need nothing but the server it came from.
    const foreign = [];
    page.on("request", (r) => {
      if (!r.url().startsWith(base.href) && !r.url().startsWith("data:")) foreign.push(r.url());
    });
    const read = await body({ page, opt, base, url, ctx });
    console.log(
      JSON.stringify({
        ...read,
        page_errors: pageErrors,
        console_errors: consoleErrors,
        foreign_requests: foreign,
      }),
    );
  } catch (e) {
    console.error(`${name}: ${e && e.stack ? e.stack : e}`);
    process.exitCode = 1;
  } finally {
    clearTimeout(deadline);
    if (ctx) await ctx.close();
    rmSync(profile, { recursive: true, force: true });
  }
}
