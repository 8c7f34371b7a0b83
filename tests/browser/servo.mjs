// Drives the tuning page's PID+FF form and servo-filter list in Debian's headless Chromium
// (tests/serve.rs runs it): switch the axis to PID+FF through the gain form (a derivative
// gain the card accepts, then a negative one it refuses), then add a notch, edit it, send one
// above Nyquist (refused), add a low-pass and clear the notch, each through the page's own
// controls; print one JSON object with what the page showed and what the server then held.
//
//   node servo.mjs 'http://127.0.0.1:PORT/#token=TOKEN' '{"kd": 0.0004, "bad_kd": -1}'
//
// (The command line, the browser and the time limit: page.mjs.)
import { run } from "./page.mjs";

const WAIT = { timeout: 20000 };

await run(
  "servo.mjs",
  { kd: 0.0004, bad_kd: -1 },
  async ({ page, opt, base, url }) => {
    await page.goto(url);
    await page.waitForFunction(() => window.tuning && window.tuning.ready && window.tuning.filtersReady, null, WAIT);

    // The outcome of a form's submit: its message once it says ok or error, and the button
    // enabled again (the page's read-back after a refusal has landed).
    const outcome = async (message, button) => {
      await page.waitForFunction(
        (id) => ["ok", "error"].includes(document.getElementById(id).dataset.status),
        message,
        WAIT,
      );
      await page.waitForFunction((id) => !document.getElementById(id).disabled, button, WAIT);
      return {
        status: await page.getAttribute(`#${message}`, "data-status"),
        message: await page.textContent(`#${message}`),
      };
    };
    const clear = (id) =>
      page.evaluate((id) => {
        const m = document.getElementById(id);
        m.dataset.status = "";
        m.textContent = "";
      }, id);

    // ---- PID+FF through the gain form ----
    const lawBefore = await page.evaluate(() => tuning.gains.law);
    await page.selectOption("#gain-law", "pidff");
    // The form starts from the card's default tuning.
    const prefilled = await page.evaluate(() => {
      const out = {};
      for (const el of document.querySelectorAll("#pidff-fields input")) out[el.dataset.key] = el.value;
      return out;
    });
    const pidffVisible = await page.isVisible("#gain-pidff-kd");
    const applyKd = async (kd) => {
      await clear("gain-message");
      await page.selectOption("#gain-law", "pidff");
      await page.fill("#gain-pidff-kd", String(kd));
      await page.click("#gain-apply");
      const o = await outcome("gain-message", "gain-apply");
      return {
        ...o,
        held_kd: await page.getAttribute("#held-pidff-kd", "data-value"),
        held_law: await page.textContent("#gain-held-law"),
        server: await page.evaluate(() => api("/api/gains")),
      };
    };
    const goodGain = await applyKd(opt.kd);
    const badGain = await applyKd(opt.bad_kd);

    // ---- the filter list ----
    const rows = () =>
      page.evaluate(() =>
        Array.from(document.querySelectorAll("#filter-rows tr")).map((tr) => ({
          id: tr.id,
          kind: tr.dataset.kind,
          params: tr.querySelector(".params").textContent,
          coeffs: tr.querySelector(".coeffs").textContent,
        })),
      );
    const setFilter = async (slot, kind, values) => {
      await clear("filter-message");
      await page.selectOption("#filter-slot", String(slot));
      await page.selectOption("#filter-kind", kind);
      for (const [k, v] of Object.entries(values)) await page.fill(`#filter-${k}`, String(v));
      await page.click("#filter-set");
      const o = await outcome("filter-message", "filter-set");
      return { ...o, rows: await rows(), server: await page.evaluate(() => api("/api/filters")) };
    };
    const rowsBefore = await rows();
    const notch = await setFilter(1, "notch", { freq_hz: 24, damping: 0.2, depth_db: -20 });
    // Edit: the row's button fills the form with what the card holds.
    await page.click("#filter-edit-1");
    const editForm = await page.evaluate(() => ({
      slot: document.getElementById("filter-slot").value,
      kind: document.getElementById("filter-kind").value,
      freq_hz: document.getElementById("filter-freq_hz").value,
      damping: document.getElementById("filter-damping").value,
      depth_db: document.getElementById("filter-depth_db").value,
      freq2_visible: !document.getElementById("filter-field-freq2_hz").hidden,
    }));
    const edited = await setFilter(1, "notch", { freq_hz: 30 });
    const refused = await setFilter(1, "notch", { freq_hz: 6000 });
    const lowpass = await setFilter(3, "lowpass", { freq_hz: 800, damping: 0.7 });
    await clear("filter-message");
    await page.click("#filter-clear-1");
    const cleared = { ...(await outcome("filter-message", "filter-set")), rows: await rows(),
      server: await page.evaluate(() => api("/api/filters")) };
    return {
      law_before: lawBefore,
      pidff_visible: pidffVisible,
      prefilled,
      good_gain: goodGain,
      bad_gain: badGain,
      rows_before: rowsBefore,
      notch,
      edit_form: editForm,
      edited,
      refused,
      lowpass,
      cleared,
    };
  },
);
