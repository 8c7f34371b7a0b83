// The tuning page's frequency response (layout 1.12): a form that posts a sweep to
// POST /api/freq (the sine on the position reference, the closed loop, or on the servo
// output, the plant), and the answer, `mcctl freq --json`'s object, drawn as a Bode plot:
// gain (dB) and phase (degrees) over log frequency, with the resonances found listed. Uses
// app.js's `api`, `$`, `setMessage`, `numberOf` and `chartWidth` (loaded before this file).
// `window.tuning.sweep` holds the last answer; `tuning.charts.bodeGain` and
// `tuning.charts.bodePhase` the two charts (`u.data`: exactly what each plots; app.js resizes
// them with the others).
"use strict";

const BODE_COLORS = { gain: "#2563eb", phase: "#e8590c" };
// The amplitude the form proposes for each mode, as `mcctl freq` does: user units on the
// reference, volts on the servo output.
const SWEEP_AMPLITUDE = { closed_loop: 100, plant: 0.5 };

const hzAxis = {
  label: "Hz (log)",
  // A log scale's splits between the labelled decades come as null: no label.
  values: (u, splits) => splits.map((v) => (v == null ? "" : v >= 10 ? v.toFixed(0) : String(Number(v.toPrecision(2))))),
};

function bodeChart(el, title, label, scale, color) {
  const opts = {
    title,
    width: chartWidth(el),
    height: 210,
    scales: { x: { time: false, distr: 3 } },
    series: [
      { label: "Hz" },
      { label, stroke: color, width: 1.5, scale, points: { show: true, size: 5 } },
    ],
    axes: [hzAxis, { scale, label, size: 60 }],
  };
  return new uPlot(opts, [[], []], el);
}

function plotSweep(r) {
  const p = r.points;
  const hz = p.map((x) => x.hz);
  tuning.charts.bodeGain.setData([hz, p.map((x) => x.gain_db)]);
  tuning.charts.bodePhase.setData([hz, p.map((x) => x.phase_deg)]);
  const what = r.mode === "plant" ? "plant X/U" : "closed loop X/R";
  $("sweep-title").textContent = `${what}, ${p.length} points from ${hz[0]} to ${hz[hz.length - 1]} Hz`;
  const list = $("sweep-resonances");
  list.textContent = "";
  const found = [...r.resonances.map((x) => [what, x]),
    ...(r.mode === "plant" ? [] : r.plant_resonances.map((x) => ["plant", x]))];
  if (found.length === 0) {
    const li = document.createElement("li");
    li.className = "none";
    li.textContent = `no resonance found (${what})`;
    list.appendChild(li);
  }
  for (const [curve, x] of found) {
    const li = document.createElement("li");
    li.dataset.hz = String(x.hz);
    li.dataset.kind = x.kind;
    li.textContent = `${curve}: ${x.name}`;
    list.appendChild(li);
  }
}

async function runSweep() {
  const msg = $("sweep-message");
  let body;
  try {
    body = {
      axis: tuning.info.axis,
      mode: $("sweep-mode").value,
      from_hz: numberOf($("sweep-from"), "from"),
      to_hz: numberOf($("sweep-to"), "to"),
      points: numberOf($("sweep-points"), "points"),
      amplitude: numberOf($("sweep-amplitude"), "the amplitude"),
      cycles: numberOf($("sweep-cycles"), "cycles"),
      settle_s: numberOf($("sweep-settle"), "settle"),
      enable: $("enable").checked,
    };
    if (!Number.isInteger(body.points) || body.points < 1) {
      $("sweep-points").classList.add("invalid");
      throw new Error(`points must be a whole number of at least 1: "${$("sweep-points").value}"`);
    }
    if (!Number.isInteger(body.cycles) || body.cycles < 1) {
      $("sweep-cycles").classList.add("invalid");
      throw new Error(`cycles must be a whole number of at least 1: "${$("sweep-cycles").value}"`);
    }
  } catch (e) {
    setMessage(msg, "error", e.message);
    return;
  }
  $("sweep-run").disabled = true;
  setMessage(msg, "busy", "sweeping…");
  try {
    const r = await api("/api/freq", body);
    tuning.sweep = r;
    plotSweep(r);
    setMessage(msg, r.complete ? "ok" : "error",
      `Swept ${r.points.length} points; ${r.resonances.length} resonance(s) found.`);
  } catch (e) {
    const kind = e.kind ? ` (${e.kind})` : "";
    const who = e.status === 422 ? "The card refused this sweep" : "No sweep";
    setMessage(msg, "error", `${who}: ${e.message}${kind}.`);
  } finally {
    $("sweep-run").disabled = false;
  }
}

function startBode() {
  const c = tuning.charts;
  c.bodeGain = bodeChart($("bode-gain"), "Gain", "gain, dB", "dB", BODE_COLORS.gain);
  c.bodePhase = bodeChart($("bode-phase"), "Phase", "phase, deg", "deg", BODE_COLORS.phase);
  const rate = tuning.info.servo_rate_hz;
  $("sweep-axis").value = String(tuning.info.axis);
  $("sweep-from").value = "5";
  $("sweep-to").value = String(Math.min(1000, rate / 4));
  $("sweep-to-max").textContent = `Hz (at most ${rate / 4})`;
  $("sweep-points").value = "40";
  $("sweep-cycles").value = "4";
  $("sweep-settle").value = "0.2";
  const mode = $("sweep-mode");
  const showMode = () => {
    $("sweep-amplitude").value = String(SWEEP_AMPLITUDE[mode.value]);
    $("sweep-amplitude-unit").textContent = mode.value === "plant" ? "V on the servo output" : "units on the reference";
  };
  mode.addEventListener("change", showMode);
  showMode();
  $("sweep-form").addEventListener("submit", (e) => {
    e.preventDefault();
    runSweep();
  });
  tuning.bodeReady = true;
}

// app.js fills `tuning.info` and the charts first.
(function waitForPage() {
  if (window.tuning && window.tuning.ready) startBode();
  else setTimeout(waitForPage, 20);
})();
