// Drives the tuning page's frequency-response panel in Debian's headless Chromium
// (tests/serve.rs runs it): a sweep the card refuses (from above to), then a small sweep
// through the page's own form; print one JSON object with what the page showed (the
// message, the charts' data, the resonances listed) and what the server answered.
//
//   node bode.mjs 'http://127.0.0.1:PORT/#token=TOKEN' '{"from": 10, "to": 60, "points": 4,
//     "amplitude": 100, "cycles": 2, "settle": 0.05, "screenshot": "freq.png"}'
//
// With `screenshot`, it saves the frequency-response panel after the sweep.
// (The command line, the browser and the time limit: page.mjs.)
import { run } from "./page.mjs";

const WAIT = { timeout: 30000 };

await run(
  "bode.mjs",
  { from: 10, to: 60, points: 4, amplitude: 100, cycles: 2, settle: 0.05 },
  async ({ page, opt, base, url }) => {
    // The server's own answer to the page's sweep, as it went over the wire.
    const answers = [];
    page.on("response", async (r) => {
      if (new URL(r.url()).pathname === "/api/freq") answers.push({ status: r.status(), body: await r.text() });
    });

    await page.goto(url);
    await page.waitForFunction(() => window.tuning && window.tuning.ready && window.tuning.bodeReady, null, WAIT);
    const defaults = await page.evaluate(() => ({
      axis: document.getElementById("sweep-axis").value,
      mode: document.getElementById("sweep-mode").value,
      from: document.getElementById("sweep-from").value,
      to: document.getElementById("sweep-to").value,
      points: document.getElementById("sweep-points").value,
      amplitude: document.getElementById("sweep-amplitude").value,
    }));

    const sweep = async (from, to) => {
      await page.evaluate(() => {
        const m = document.getElementById("sweep-message");
        m.dataset.status = "";
        m.textContent = "";
      });
      const before = answers.length;
      await page.selectOption("#sweep-mode", "closed_loop");
      await page.fill("#sweep-from", String(from));
      await page.fill("#sweep-to", String(to));
      await page.fill("#sweep-points", String(opt.points));
      await page.fill("#sweep-amplitude", String(opt.amplitude));
      await page.fill("#sweep-cycles", String(opt.cycles));
      await page.fill("#sweep-settle", String(opt.settle));
      await page.check("#enable");
      await page.click("#sweep-run");
      await page.waitForFunction(
        () => ["ok", "error"].includes(document.getElementById("sweep-message").dataset.status),
        null,
        WAIT,
      );
      await page.waitForFunction(() => !document.getElementById("sweep-run").disabled, null, WAIT);
      // The response's body is read asynchronously: wait for it to land.
      for (let i = 0; i < 200 && answers.length === before; i++) await new Promise((r) => setTimeout(r, 10));
      return {
        status: await page.getAttribute("#sweep-message", "data-status"),
        message: await page.textContent("#sweep-message"),
        title: await page.textContent("#sweep-title"),
        gain: await page.evaluate(() => tuning.charts.bodeGain.data),
        phase: await page.evaluate(() => tuning.charts.bodePhase.data),
        x_log: await page.evaluate(() => tuning.charts.bodeGain.scales.x.distr),
        resonances: await page.evaluate(() =>
          Array.from(document.querySelectorAll("#sweep-resonances li")).map((li) => li.textContent)),
        answer: answers.length > before ? answers[answers.length - 1] : null,
      };
    };
    const refused = await sweep(opt.to, opt.from);
    const swept = await sweep(opt.from, opt.to);
    if (opt.screenshot) await page.locator("#freq").screenshot({ path: opt.screenshot });
    return {
      defaults,
      refused,
      swept,
    };
  },
);
