// The tuning page's servo-output filters (layout 1.11): the axis's four biquad slots as the
// card holds them (GET /api/filters), and a form that sets one (notch, low-pass, lead/lag or
// raw coefficients; POST /api/filters) or clears it. Uses app.js's `api`, `$`, `setMessage`
// and `numberOf` (loaded before this file). `window.tuning.filters` holds the slots as last
// read from the server.
"use strict";

const FILTER_FIELDS = {
  notch: [
    ["freq_hz", "f", "Hz, centre"],
    ["damping", "ζ", "damping (width), 0..10"],
    ["depth_db", "depth", "dB at the centre, −120..0"],
  ],
  lowpass: [
    ["freq_hz", "f", "Hz, corner"],
    ["damping", "ζ", "damping, 0..10"],
  ],
  lead_lag: [
    ["freq_hz", "f_zero", "Hz, the zero"],
    ["freq2_hz", "f_pole", "Hz, the pole"],
  ],
  raw: [
    ["b0", "b0", ""],
    ["b1", "b1", ""],
    ["b2", "b2", ""],
    ["a1", "a1", ""],
    ["a2", "a2", "(a0 = 1)"],
  ],
};
const FILTER_KEYS = ["freq_hz", "damping", "depth_db", "freq2_hz", "b0", "b1", "b2", "a1", "a2"];
const FILTER_NAMES = { none: "empty", notch: "notch", lowpass: "low-pass", lead_lag: "lead/lag", raw: "raw" };

function filterText(f) {
  const fields = FILTER_FIELDS[f.kind];
  if (!fields) return "–";
  return fields.map(([key, sym, unit]) => `${sym} = ${f[key]}${unit.startsWith("Hz") ? " Hz" : unit.startsWith("dB") ? " dB" : ""}`).join(", ");
}

function buildFilterForm() {
  const box = $("filter-fields");
  for (const key of FILTER_KEYS) {
    const d = document.createElement("div");
    d.className = "field";
    d.id = `filter-field-${key}`;
    d.innerHTML =
      `<label for="filter-${key}" id="filter-label-${key}">${key}</label>` +
      `<input id="filter-${key}" type="text" inputmode="decimal" data-key="${key}">` +
      `<span class="unit" id="filter-unit-${key}"></span>`;
    box.appendChild(d);
  }
  const kind = $("filter-kind");
  const showKind = () => {
    const fields = FILTER_FIELDS[kind.value];
    for (const key of FILTER_KEYS) {
      const f = fields.find(([k]) => k === key);
      $(`filter-field-${key}`).hidden = !f;
      if (f) {
        $(`filter-label-${key}`).textContent = f[1];
        $(`filter-unit-${key}`).textContent = f[2];
      }
    }
  };
  kind.addEventListener("change", showKind);
  showKind();
}

function fillFilters(r) {
  tuning.filters = r;
  $("filter-rate").textContent = `designed at ${r.servo_rate_hz} Hz (Nyquist ${r.servo_rate_hz / 2} Hz)`;
  const body = $("filter-rows");
  body.textContent = "";
  for (const s of r.slots) {
    const tr = document.createElement("tr");
    tr.id = `filter-slot-${s.slot}`;
    tr.dataset.kind = s.filter.kind;
    const coeffs = s.coeffs ? s.coeffs.map((c) => c.toPrecision(6)).join(", ") : "–";
    tr.innerHTML =
      `<td>${s.slot}</td><td class="kind">${FILTER_NAMES[s.filter.kind]}</td>` +
      `<td class="params">${filterText(s.filter)}</td><td class="coeffs">${coeffs}</td>` +
      `<td><button type="button" class="edit" id="filter-edit-${s.slot}"${s.filter.kind === "none" ? " disabled" : ""}>Edit</button> ` +
      `<button type="button" class="clear" id="filter-clear-${s.slot}"${s.filter.kind === "none" ? " disabled" : ""}>Clear</button></td>`;
    body.appendChild(tr);
    tr.querySelector(".edit").addEventListener("click", () => editFilter(s));
    tr.querySelector(".clear").addEventListener("click", () => sendFilter(s.slot, { kind: "none" }, "cleared"));
  }
}

function editFilter(s) {
  $("filter-slot").value = String(s.slot);
  $("filter-kind").value = s.filter.kind;
  $("filter-kind").dispatchEvent(new Event("change"));
  for (const [key] of FILTER_FIELDS[s.filter.kind]) $(`filter-${key}`).value = String(s.filter[key]);
}

async function sendFilter(slot, filter, what) {
  const msg = $("filter-message");
  $("filter-set").disabled = true;
  setMessage(msg, "busy", "sending…");
  try {
    fillFilters(await api("/api/filters", { slot, filter }));
    setMessage(msg, "ok", `Slot ${slot} ${what}.`);
  } catch (e) {
    const kind = e.kind ? ` (${e.kind})` : "";
    const who = e.status === 422 ? "The card refused this filter" : "Not applied";
    setMessage(msg, "error", `${who}: ${e.message}${kind}. The card keeps the filters listed.`);
    try {
      fillFilters(await api("/api/filters"));
    } catch (e2) {
      /* the message above stands */
    }
  } finally {
    $("filter-set").disabled = false;
  }
}

function setFilter() {
  const kind = $("filter-kind").value;
  const filter = { kind };
  try {
    for (const [key, sym] of FILTER_FIELDS[kind]) filter[key] = numberOf($(`filter-${key}`), sym);
  } catch (e) {
    setMessage($("filter-message"), "error", e.message);
    return;
  }
  const slot = Number($("filter-slot").value);
  sendFilter(slot, filter, `set to a ${FILTER_NAMES[kind]}`);
}

async function startFilters() {
  buildFilterForm();
  $("filter-form").addEventListener("submit", (e) => {
    e.preventDefault();
    setFilter();
  });
  $("filter-reload").addEventListener("click", () => {
    api("/api/filters").then(
      (r) => {
        fillFilters(r);
        setMessage($("filter-message"), "ok", "Reloaded.");
      },
      (e) => setMessage($("filter-message"), "error", e.message),
    );
  });
  try {
    fillFilters(await api("/api/filters"));
  } catch (e) {
    setMessage($("filter-message"), "error", `filters: ${e.message}`);
  }
  tuning.filtersReady = true;
}

startFilters();
