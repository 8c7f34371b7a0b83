// The tuning page of `mcctl serve`: live plots from the scope stream, the step and move
// tests with their figures, and the servo gains. Everything it shows comes from /api/*.
//
// Every API request carries the server's token, which the page takes from the address
// `mcctl serve` printed (`http://ADDR/#token=TOKEN`: a fragment, never sent to a server in a
// request line or a Referer), keeps for this tab in sessionStorage (no other origin can read
// it) and takes off the address bar. The server holds it nowhere a page can fetch.
//
// For tests and tools, `window.tuning` holds the page's state: `charts` (the uPlot
// instances; `u.data` is exactly what each plots), `lastTest` (the last test's id, figures
// and, through `series`, the arrays its charts plot), `gains` (as last read from the server)
// `live` (the stream's state and how many points it has plotted), from servo.js, `filters`
// (the servo output's filter slots as last read from the server) and, from bode.js, `sweep`
// (the last frequency sweep's answer).
"use strict";

const LIVE_WINDOW_S = 10;
const COLORS = {
  cmd: "#2563eb",
  act: "#e8590c",
  ferr: "#b3261e",
  dac: "#1b7f3b",
  band: "#7d8796",
};

const GAIN_FIELDS = {
  ffpiv: [
    ["kp", "K_P", "1/s, position gain"],
    ["ki", "K_I", "1/s, velocity-loop integral"],
    ["kv", "K_V", "V per count/s, velocity loop"],
    ["kvff", "K_VFF", "velocity feed-forward, 0..2"],
    ["kaff", "K_AFF", "V per count/s², acceleration feed-forward"],
    ["vel_filter_hz", "f_v", "Hz, measured-velocity filter"],
  ],
  pdplus: [
    ["kp", "k_p", "V/count"],
    ["kd", "k_d", "V per count/s"],
    ["kv", "k_v", "V per count/s of reference velocity"],
    ["ka", "k_a", "V per count/s² of reference acceleration"],
    ["kc", "K_c", "(rad/s)/V, drive model"],
    ["tau", "τ", "s, drive model"],
    ["ke", "K_e", "counts/rad, drive model"],
    ["umax", "U_max", "V, drive limit"],
  ],
  pidff: [
    ["kp", "k_p", "V/count"],
    ["ki", "k_i", "V/(count·s), integral (anti-windup at the DAC limit)"],
    ["kd", "k_d", "V per count/s, derivative"],
    ["d_filter_hz", "f_d", "Hz, derivative filter"],
    ["kvff", "k_vff", "V per count/s, velocity feed-forward"],
    ["kaff", "k_aff", "V per count/s², acceleration feed-forward"],
    ["friction", "F_c", "V, Coulomb friction feed-forward"],
    ["friction_deadband", "v_0", "counts/s, no friction term up to |v_ref|"],
  ],
};
const LAW_NAMES = { ffpiv: "FFPIV", pdplus: "PD+", pidff: "PID+FF" };

const tuning = {
  ready: false,
  info: null,
  charts: {},
  lastTest: null,
  gains: null,
  live: { state: "connecting", points: 0, lastTick: 0, batches: 0 },
};
window.tuning = tuning;

const $ = (id) => document.getElementById(id);

const TOKEN_KEY = "motioncard-serve-token";
const NO_TOKEN =
  "this page needs the server's token: open the address `mcctl serve` printed, with its #token=…";

// The token from the address (then kept for this tab and taken off the address bar), or the
// one kept from it; null when neither.
function takeToken() {
  const m = /^#token=([A-Za-z0-9._~-]+)$/.exec(location.hash);
  let kept = null;
  try {
    if (m) sessionStorage.setItem(TOKEN_KEY, m[1]);
    kept = sessionStorage.getItem(TOKEN_KEY);
  } catch (e) {
    /* storage disabled: the token lives as long as the page */
  }
  if (m) history.replaceState(null, "", location.pathname + location.search);
  return m ? m[1] : kept;
}
const token = takeToken();

function setMessage(el, status, text) {
  el.dataset.status = status;
  el.textContent = text;
}

// A number typed in a field, or an error naming the field.
function numberOf(input, name) {
  const v = Number(input.value.trim());
  if (input.value.trim() === "" || !Number.isFinite(v)) {
    input.classList.add("invalid");
    throw new Error(`${name} is not a number: "${input.value}"`);
  }
  input.classList.remove("invalid");
  return v;
}

async function api(path, body) {
  if (!token) throw new Error(NO_TOKEN);
  const headers = { authorization: `Bearer ${token}` };
  const init = body === undefined ? { headers } : {
    method: "POST",
    headers: { ...headers, "content-type": "application/json" },
    body: JSON.stringify(body),
  };
  const r = await fetch(path, init);
  let j = null;
  try {
    j = await r.json();
  } catch (e) {
    throw new Error(`${path}: HTTP ${r.status}, not JSON`);
  }
  if (!r.ok) {
    const err = new Error(j && j.error ? j.error : `HTTP ${r.status}`);
    err.kind = j ? j.kind : null;
    err.status = r.status;
    throw err;
  }
  return j;
}

// ---- charts ----

function chartWidth(el) {
  return Math.max(300, el.clientWidth || el.parentElement.clientWidth || 600);
}

const msAxis = {
  label: "ms",
  values: (u, splits) => splits.map((v) => (v * 1000).toFixed(0)),
};
const sAxis = {
  label: "s (card time)",
  values: (u, splits) => splits.map((v) => v.toFixed(1)),
};

function positionChart(el, title, xAxis, withBand) {
  const series = [
    { label: "t" },
    { label: "command", stroke: COLORS.cmd, width: 1.5, scale: "counts" },
    { label: "actual", stroke: COLORS.act, width: 1.5, scale: "counts" },
  ];
  if (withBand) {
    series.push({ label: "band +", stroke: COLORS.band, dash: [4, 4], width: 1, scale: "counts" });
    series.push({ label: "band −", stroke: COLORS.band, dash: [4, 4], width: 1, scale: "counts" });
  }
  const opts = {
    title,
    width: chartWidth(el),
    height: 210,
    scales: { x: { time: false } },
    series,
    axes: [xAxis, { scale: "counts", label: "position, counts", size: 70 }],
    legend: { live: true },
  };
  return new uPlot(opts, series.map(() => []), el);
}

function errorChart(el, title, xAxis) {
  const opts = {
    title,
    width: chartWidth(el),
    height: 210,
    scales: { x: { time: false } },
    series: [
      { label: "t" },
      { label: "following error", stroke: COLORS.ferr, width: 1.5, scale: "counts" },
      { label: "DAC", stroke: COLORS.dac, width: 1.5, scale: "V" },
    ],
    axes: [
      xAxis,
      { scale: "counts", label: "following error, counts", size: 60 },
      { scale: "V", label: "DAC, V", side: 1, grid: { show: false }, size: 50 },
    ],
  };
  return new uPlot(opts, [[], [], []], el);
}

// A dashed vertical line at the settling time, and a shaded 10–90 % rise window.
function markFigures(u) {
  const t = tuning.lastTest;
  if (!t || !t.figures) return;
  const f = t.figures;
  const ctx = u.ctx;
  const top = u.bbox.top;
  const h = u.bbox.height;
  ctx.save();
  if (f.settling_time !== null) {
    const x = u.valToPos(f.start_time + f.settling_time, "x", true);
    ctx.strokeStyle = COLORS.band;
    ctx.setLineDash([6, 4]);
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(x, top);
    ctx.lineTo(x, top + h);
    ctx.stroke();
    ctx.fillStyle = COLORS.band;
    ctx.font = `${12 * devicePixelRatio}px system-ui`;
    ctx.fillText("settled", x + 4, top + h - 8 * devicePixelRatio);
  }
  ctx.restore();
}

function setupCharts() {
  const c = tuning.charts;
  c.livePos = positionChart($("live-pos"), "Command and actual position", sAxis, false);
  c.liveErr = errorChart($("live-err"), "Following error and DAC", sAxis);
  c.testPos = positionChart($("test-pos"), "Position", msAxis, true);
  c.testPos.hooks.draw = c.testPos.hooks.draw || [];
  c.testPos.hooks.draw.push(markFigures);
  c.testErr = errorChart($("test-err"), "Following error and DAC", msAxis);
  window.addEventListener("resize", () => {
    for (const [name, u] of Object.entries(c)) {
      const el = $({
        livePos: "live-pos", liveErr: "live-err", testPos: "test-pos", testErr: "test-err",
        bodeGain: "bode-gain", bodePhase: "bode-phase",
      }[name]);
      u.setSize({ width: chartWidth(el), height: 210 });
    }
  });
}

// ---- live stream ----

const live = { t: [], cmd: [], act: [], ferr: [], dac: [], pending: false };

function setLiveState(state, text) {
  tuning.live.state = state;
  const el = $("live-state");
  el.dataset.state = state;
  el.textContent = text;
}

function drawLive() {
  live.pending = false;
  tuning.charts.livePos.setData([live.t, live.cmd, live.act]);
  tuning.charts.liveErr.setData([live.t, live.ferr, live.dac]);
  tuning.live.points = live.t.length;
}

// Ticks between two display points of the stream.
function liveSpacing(rate) {
  const live = tuning.info.live;
  return live.group * Math.max(1, Math.floor(rate / live.card_hz));
}

function onBatch(b) {
  const rate = b.servo_rate_hz;
  // A gap in the stream (a test had the scope): a null point, so the plot shows the gap
  // rather than a line across it.
  const prev = tuning.live.lastTick;
  if (live.t.length > 0 && b.tick[0] - prev > 2 * liveSpacing(rate)) {
    live.t.push((prev + b.tick[0]) / 2 / rate);
    for (const k of ["cmd", "act", "ferr", "dac"]) live[k].push(null);
  }
  for (let i = 0; i < b.tick.length; i++) {
    live.t.push(b.tick[i] / rate);
    live.cmd.push(b.cmd[i]);
    live.act.push(b.act[i]);
    live.ferr.push(b.ferr[i]);
    live.dac.push(b.dac[i]);
  }
  const newest = live.t[live.t.length - 1];
  let drop = 0;
  while (drop < live.t.length && live.t[drop] < newest - LIVE_WINDOW_S) drop++;
  if (drop > 0) {
    for (const k of ["t", "cmd", "act", "ferr", "dac"]) live[k].splice(0, drop);
  }
  tuning.live.lastTick = b.tick[b.tick.length - 1];
  tuning.live.batches += 1;
  const st = $("axis-state");
  st.dataset.state = b.state;
  st.textContent = `axis ${tuning.info.axis}: ${b.state}`;
  if (tuning.live.state !== "live") setLiveState("live", "live");
  if (!live.pending) {
    live.pending = true;
    requestAnimationFrame(drawLive);
  }
}

function startLive() {
  // An EventSource sets no header: the stream alone takes the token in its query.
  const es = new EventSource(`/api/live?token=${encodeURIComponent(token)}`);
  es.addEventListener("samples", (e) => onBatch(JSON.parse(e.data)));
  es.addEventListener("paused", (e) => {
    const j = JSON.parse(e.data);
    setLiveState("paused", `live: paused, the ${j.for} owns the scope`);
  });
  es.addEventListener("resumed", () => setLiveState("live", "live"));
  es.addEventListener("failure", (e) => {
    const j = JSON.parse(e.data);
    setLiveState("error", j.error);
  });
  es.onerror = () => {
    if (es.readyState === EventSource.CLOSED) {
      setLiveState("error", "live: the server refused the stream (reload the page)");
    } else if (tuning.live.state !== "error") {
      setLiveState("connecting", "live: reconnecting…");
    }
  };
}

// ---- tests ----

function show(id, value, text) {
  const el = $(id);
  el.dataset.value = value === null || value === undefined ? "" : String(value);
  el.textContent = text;
}

const ms = (s) => (s * 1000).toFixed(2) + " ms";

function showFigures(run) {
  const f = run.figures;
  $("figures").dataset.testId = "";
  show("fig-kind", run.kind, `${run.kind} test, axis ${run.axis}`);
  show("fig-step", f.step, `${f.step} counts (${f.start} → ${f.target})`);
  show("fig-rise", f.rise_time, f.rise_time === null ? "not reached (the actual never got to 90 %)" : ms(f.rise_time));
  show("fig-overshoot", f.overshoot_pct, f.overshoot_pct.toFixed(2) + " %");
  show(
    "fig-settling",
    f.settling_time,
    f.settling_time === null ? "not settled within the capture" : ms(f.settling_time),
  );
  show(
    "fig-peak-ferr",
    f.peak_following_error,
    `${f.peak_following_error.toFixed(2)} counts at ${(f.peak_following_error_time * 1000).toFixed(1)} ms`,
  );
  show("fig-band", f.band, `±${f.band.toFixed(2)} counts`);
  show(
    "fig-command",
    f.command_end_time,
    run.kind === "step" ? `${ms(f.command_end_time)} (a step: on its first tick)` : ms(f.command_end_time),
  );
  show("fig-outcome", run.in_position, `${run.outcome}; ${run.end_state}`);
  $("test-title").textContent =
    `${run.kind} of ${run.distance} counts, ${run.samples.t.length} samples at ${run.servo_rate_hz} Hz`;
}

function plotTest(run) {
  const s = run.samples;
  const f = run.figures;
  const hi = s.t.map(() => f.target + f.band);
  const lo = s.t.map(() => f.target - f.band);
  tuning.charts.testPos.setData([s.t, s.cmd, s.act, hi, lo]);
  tuning.charts.testErr.setData([s.t, s.ferr, s.dac]);
}

async function runTest(kind) {
  const msg = $("test-message");
  let body;
  try {
    if (kind === "step") {
      body = { kind, distance: numberOf($("step-size"), "the step") };
    } else {
      body = {
        kind,
        distance: numberOf($("move-distance"), "the distance"),
        limits: {
          vmax: numberOf($("move-vmax"), "vmax"),
          amax: numberOf($("move-amax"), "amax"),
          jmax: numberOf($("move-jmax"), "jmax"),
        },
      };
    }
  } catch (e) {
    setMessage(msg, "error", e.message);
    return;
  }
  body.enable = $("enable").checked;
  for (const b of [$("step-run"), $("move-run")]) b.disabled = true;
  setMessage(msg, "busy", `${kind} test running…`);
  try {
    const run = await api("/api/tests", body);
    tuning.lastTest = {
      id: run.id,
      kind: run.kind,
      figures: run.figures,
      outcome: run.outcome,
      in_position: run.in_position,
      // What the test's charts plot: their own data arrays.
      get series() {
        const p = tuning.charts.testPos.data;
        const e = tuning.charts.testErr.data;
        return { t: p[0], cmd: p[1], act: p[2], ferr: e[1], dac: e[2] };
      },
    };
    plotTest(run);
    showFigures(run);
    $("figures").dataset.testId = String(run.id);
    setMessage(msg, run.in_position ? "ok" : "error", `${kind} test ${run.id}: ${run.outcome}`);
  } catch (e) {
    setMessage(msg, "error", `${kind} test: ${e.message}`);
  } finally {
    for (const b of [$("step-run"), $("move-run")]) b.disabled = false;
  }
}

// ---- gains ----

function buildGainFields() {
  for (const [law, fields] of Object.entries(GAIN_FIELDS)) {
    const box = $(`${law}-fields`);
    for (const [key, symbol, unit] of fields) {
      const d = document.createElement("div");
      d.className = "field";
      d.innerHTML =
        `<label for="gain-${law}-${key}">${symbol}</label>` +
        `<input id="gain-${law}-${key}" type="text" inputmode="decimal" data-key="${key}">` +
        `<span class="unit">${unit}</span>` +
        `<span class="held" id="held-${law}-${key}" data-value="">card: –</span>`;
      box.appendChild(d);
    }
  }
  const law = $("gain-law");
  const showLaw = () => {
    for (const l of Object.keys(GAIN_FIELDS)) $(`${l}-fields`).hidden = l !== law.value;
  };
  law.addEventListener("change", showLaw);
  showLaw();
}

function fillGains(g) {
  tuning.gains = g;
  $("gain-held-law").textContent = `the axis runs ${LAW_NAMES[g.law]}`;
  $("gain-source").textContent = g.source;
  for (const [law, values] of [["ffpiv", g.ffpiv], ["pdplus", g.pdplus], ["pidff", g.pidff]]) {
    for (const [key] of GAIN_FIELDS[law]) {
      const held = $(`held-${law}-${key}`);
      const input = $(`gain-${law}-${key}`);
      input.classList.remove("invalid");
      if (values) {
        input.value = String(values[key]);
        held.dataset.value = String(values[key]);
        held.textContent = `card: ${Number(values[key]).toPrecision(6)}`;
      } else {
        // PID+FF on an axis that runs another law: the card's default tuning to start from.
        const start = law === "pidff" ? tuning.info.defaults.pidff : null;
        if (start && input.value === "") input.value = String(start[key]);
        held.dataset.value = "";
        held.textContent = "card: –";
      }
    }
  }
  $("gain-law").value = g.law;
  $("gain-law").dispatchEvent(new Event("change"));
}

async function loadGains() {
  fillGains(await api("/api/gains"));
}

async function applyGains() {
  const msg = $("gain-message");
  const law = $("gain-law").value;
  const body = { law };
  try {
    for (const [key, symbol] of GAIN_FIELDS[law]) {
      body[key] = numberOf($(`gain-${law}-${key}`), symbol);
    }
  } catch (e) {
    setMessage(msg, "error", e.message);
    return;
  }
  $("gain-apply").disabled = true;
  setMessage(msg, "busy", "applying…");
  try {
    const g = await api("/api/gains", body);
    fillGains(g);
    setMessage(msg, "ok", `Applied: the card accepted the ${LAW_NAMES[law]} gains.`);
  } catch (e) {
    const kind = e.kind ? ` (${e.kind})` : "";
    const who = e.status === 422 ? "The card refused these gains" : "Not applied";
    setMessage(msg, "error", `${who}: ${e.message}${kind}. The card keeps the gains shown as "card:".`);
    // Show what the card holds now, next to what was typed.
    try {
      const g = await api("/api/gains");
      tuning.gains = g;
      for (const [l, values] of [["ffpiv", g.ffpiv], ["pdplus", g.pdplus], ["pidff", g.pidff]]) {
        for (const [key] of GAIN_FIELDS[l]) {
          const held = $(`held-${l}-${key}`);
          held.dataset.value = values ? String(values[key]) : "";
          held.textContent = values ? `card: ${Number(values[key]).toPrecision(6)}` : "card: –";
        }
      }
    } catch (e2) {
      /* the message above stands */
    }
  } finally {
    $("gain-apply").disabled = false;
  }
}

// ---- start ----

async function main() {
  const info = await api("/api/info");
  tuning.info = info;
  $("card-info").textContent =
    `${info.uri}, axis ${info.axis} of ${info.axes}, servo ${info.servo_rate_hz} Hz, firmware ${info.firmware}`;
  $("band-rule").textContent =
    `±${info.band.fraction * 100} % of the step, at least ±${info.band.min} counts,`;
  $("step-size").value = String(info.defaults.step);
  $("move-distance").value = String(info.defaults.distance);
  $("move-vmax").value = String(info.defaults.limits.vmax);
  $("move-amax").value = String(info.defaults.limits.amax);
  $("move-jmax").value = String(info.defaults.limits.jmax);
  setupCharts();
  buildGainFields();
  $("step-form").addEventListener("submit", (e) => {
    e.preventDefault();
    runTest("step");
  });
  $("move-form").addEventListener("submit", (e) => {
    e.preventDefault();
    runTest("move");
  });
  $("axis-reset").addEventListener("click", async () => {
    const msg = $("test-message");
    try {
      const r = await api("/api/reset", {});
      setMessage(msg, "ok", `axis ${info.axis} reset: ${r.state}`);
    } catch (e) {
      setMessage(msg, "error", `reset: ${e.message}`);
    }
  });
  $("gain-form").addEventListener("submit", (e) => {
    e.preventDefault();
    applyGains();
  });
  $("gain-reload").addEventListener("click", () => {
    loadGains().then(
      () => setMessage($("gain-message"), "ok", "Reloaded."),
      (e) => setMessage($("gain-message"), "error", e.message),
    );
  });
  startLive();
  try {
    await loadGains();
  } catch (e) {
    setMessage($("gain-message"), "error", `gains: ${e.message}`);
  }
  tuning.ready = true;
}

main().catch((e) => {
  document.body.dataset.error = e.message;
  $("card-info").textContent = `the page could not start: ${e.message}`;
});
