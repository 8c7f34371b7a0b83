// Drives the tuning page of `mcctl serve` in Debian's headless Chromium (tests/serve.rs runs
// it): load the page, wait for the live plots, run a step test, read the figures the page
// shows and the arrays its charts plot, apply a good gain and a bad one, and print one JSON
// object on stdout with everything read, for the Rust test to check. Then the guard: the page
// opened without the token, and the page's address under another name that resolves to the
// server (DNS rebinding, `evil.example`, mapped to 127.0.0.1 by the browser's resolver).
//
//   node drive.mjs 'http://127.0.0.1:PORT/#token=TOKEN' '{"step": 400, "kp": 70, "bad_kp": -5}'
//
// (The command line, the browser and the time limit: page.mjs.)
import { run } from "./page.mjs";

const REBIND = "evil.example";
const WAIT = { timeout: 20000 };

await run(
  "drive.mjs",
  { step: 400, kp: 70, bad_kp: -5, trip_step: 2000, screenshot: null },
  async ({ page, opt, base, url, ctx }) => {
    await page.goto(url);
    await page.waitForFunction(() => window.tuning && window.tuning.ready, null, WAIT);
    // The page took the token off the address bar.
    const urlAfterLoad = page.url();
    await page.waitForFunction(() => window.tuning.live.points >= 20, null, WAIT);
    const liveBefore = await page.evaluate(() => ({
      state: tuning.live.state,
      points: tuning.charts.livePos.data[0].length,
      last_tick: tuning.live.lastTick,
    }));

    // The step test, as a person runs it.
    await page.fill("#step-size", String(opt.step));
    const answer = page.waitForResponse(
      (r) => r.url().endsWith("/api/tests") && r.request().method() === "POST",
      WAIT,
    );
    await page.click("#step-run");
    const response = await answer;
    const api = await response.json();
    if (!response.ok()) throw new Error(`the step test failed: ${JSON.stringify(api)}`);
    await page.waitForFunction(
      (id) => document.getElementById("figures").dataset.testId === String(id),
      api.id,
      WAIT,
    );
    const displayed = await page.evaluate(() => {
      const out = {};
      for (const el of document.querySelectorAll("#figures td")) {
        out[el.id] = { text: el.textContent, value: el.dataset.value };
      }
      return out;
    });
    // What the charts plot: uPlot's own data arrays.
    const plotted = await page.evaluate(() => {
      const s = tuning.lastTest.series;
      const p = tuning.charts.testPos.data;
      return {
        id: tuning.lastTest.id,
        t: Array.from(s.t),
        cmd: Array.from(s.cmd),
        act: Array.from(s.act),
        ferr: Array.from(s.ferr),
        dac: Array.from(s.dac),
        band_hi: Array.from(p[3]),
        band_lo: Array.from(p[4]),
      };
    });
    const testMessage = await page.textContent("#test-message");

    // The live plots resume after the test, with samples from after it.
    const lastTick = api.samples.tick[api.samples.tick.length - 1];
    await page.waitForFunction(
      (t) => window.tuning.live.state === "live" && window.tuning.live.lastTick > t,
      lastTick,
      WAIT,
    );
    await page.waitForTimeout(500); // a few batches drawn, for the screenshot
    const liveAfter = await page.evaluate(() => {
      const d = tuning.charts.livePos.data;
      const n = d[0].length;
      return {
        state: tuning.live.state,
        points: n,
        last_tick: tuning.live.lastTick,
        cmd_last: d[1][n - 1],
        act_last: d[2][n - 1],
      };
    });
    if (opt.screenshot) await page.screenshot({ path: opt.screenshot, fullPage: true });

    // Gains: one the card accepts, then one it refuses.
    const gainsBefore = await page.evaluate(() => tuning.gains);
    const apply = async (kp) => {
      await page.evaluate(() => {
        const m = document.getElementById("gain-message");
        m.dataset.status = "";
        m.textContent = "";
      });
      await page.selectOption("#gain-law", "ffpiv");
      await page.fill("#gain-ffpiv-kp", String(kp));
      await page.click("#gain-apply");
      await page.waitForFunction(
        () => ["ok", "error"].includes(document.getElementById("gain-message").dataset.status),
        null,
        WAIT,
      );
      // Let the page's own read-back after a refusal land.
      await page.waitForFunction(() => !document.getElementById("gain-apply").disabled, null, WAIT);
      return page.evaluate(async () => ({
        status: document.getElementById("gain-message").dataset.status,
        message: document.getElementById("gain-message").textContent,
        held_kp: document.getElementById("held-ffpiv-kp").dataset.value,
        typed_kp: document.getElementById("gain-ffpiv-kp").value,
        server: await api("/api/gains"),
      }));
    };
    const good = await apply(opt.kp);
    const bad = await apply(opt.bad_kp);

    // A step beyond the following-error limit: the card trips, the page says why; then the
    // page's reset brings the axis back.
    const clear = () =>
      page.evaluate(() => {
        const m = document.getElementById("test-message");
        m.dataset.status = "";
        m.textContent = "";
      });
    const settled = () =>
      page.waitForFunction(
        () => ["ok", "error"].includes(document.getElementById("test-message").dataset.status),
        null,
        WAIT,
      );
    await clear();
    await page.fill("#step-size", String(opt.trip_step));
    await page.click("#step-run");
    await settled();
    const tripMessage = await page.textContent("#test-message");
    await clear();
    await page.click("#axis-reset");
    await settled();
    const reset = {
      status: await page.getAttribute("#test-message", "data-status"),
      message: await page.textContent("#test-message"),
    };
    // And a step runs again (powering the axis on: "power the axis on" is ticked).
    await clear();
    await page.fill("#step-size", String(opt.step));
    await page.click("#step-run");
    await settled();
    const again = {
      status: await page.getAttribute("#test-message", "data-status"),
      message: await page.textContent("#test-message"),
    };

    // The page opened without the token (a new tab: its own sessionStorage) says what it needs.
    const bare = await ctx.newPage();
    await bare.goto(base.href);
    await bare.waitForFunction(
      () => document.getElementById("card-info").textContent.includes("token"),
      null,
      WAIT,
    );
    const withoutToken = await bare.textContent("#card-info");
    // DNS rebinding: another site's name resolved to the server's address.
    const rebound = new URL(base.href);
    rebound.hostname = REBIND;
    const evil = await bare.goto(rebound.href);
    const reboundPage = { status: evil.status(), body: await evil.text() };
    await bare.close();
    return {
      url_after_load: urlAfterLoad,
      without_token: withoutToken,
      rebound: reboundPage,
      live_before: liveBefore,
      live_after: liveAfter,
      api,
      displayed,
      plotted,
      test_message: testMessage,
      gains_before: gainsBefore,
      good,
      bad,
      trip_message: tripMessage,
      reset,
      again,
    };
  },
  { viewport: { width: 1280, height: 900 }, args: ["--disable-quic", `--host-resolver-rules=MAP ${REBIND} 127.0.0.1`] },
);
