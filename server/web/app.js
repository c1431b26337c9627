// The granulab web page: a small hash-routed client of the HTTP API (docs/api.md). Views:
//   #/             jobs and sweeps with live status and progress
//   #/jobs/ID      a job: status, warnings, live curve, snapshot sections (field and slice), downloads
//   #/sweeps/ID    a sweep: overlaid curves and a table of its jobs' varied values and key values
// What each experiment shows first (its curve's axes and series, key summary values and tables) is its
// headline, from GET /v1/experiments: the page names no experiment's columns.
//   #/submit       a form built from the experiment registry, prefilled from an example (the cheapest first);
//                  its cost (dry runs) shown as it changes, a question before a long job; errors by field
// Every request carries the token kept in localStorage (asked for once, when the server answers 401).
// Pictures are the server's own SVG documents, placed inline so they scale and can be inspected.
"use strict";

const REFRESH_MS = 2000;
let timer = null;

// ---- talking to the server ------------------------------------------------------------------------

function token() { return localStorage.getItem("granulab_token") || ""; }

async function request(path, options = {}) {
  const headers = Object.assign({}, options.headers || {});
  if (token()) headers["Authorization"] = "Bearer " + token();
  const response = await fetch(path, Object.assign({}, options, { headers, cache: "no-store" }));
  if (response.status === 401) {
    document.getElementById("token-bar").hidden = false;
    throw new Error("this server needs an access token (above)");
  }
  return response;
}

async function getJson(path) {
  const response = await request(path);
  const body = await response.json();
  if (!response.ok) throw new Error(body.error ? body.error.message : "HTTP " + response.status);
  return body;
}

async function sendJson(method, path, body) {
  const response = await request(path, {
    method, headers: { "Content-Type": "application/json" }, body: body === undefined ? undefined : JSON.stringify(body),
  });
  return { status: response.status, body: await response.json() };
}

// An SVG picture from the server, inline; a note instead when there is nothing to draw yet.
// The holder shows the picture last asked for: an answer that arrives after a newer request is dropped.
async function picture(path, holder) {
  holder.dataset.wanted = path;
  const response = await request(path);
  if (holder.dataset.wanted !== path) return;
  if (!response.ok) {
    const body = await response.json().catch(() => ({}));
    if (holder.dataset.wanted === path)
      fill(holder, el("p", { class: "hint" }, body.error ? body.error.message : "HTTP " + response.status));
    return;
  }
  const text = await response.text();
  if (holder.dataset.wanted !== path) return;
  const doc = new DOMParser().parseFromString(text, "image/svg+xml");
  const svg = doc.documentElement;
  if (svg.nodeName !== "svg") return;
  fill(holder, document.importNode(svg, true));
}

// Downloads through fetch, so a token travels with them.
async function download(path, name) {
  const response = await request(path);
  if (!response.ok) return alert("download failed: HTTP " + response.status);
  const link = el("a", { href: URL.createObjectURL(await response.blob()), download: name });
  document.body.appendChild(link);
  link.click();
  setTimeout(() => { URL.revokeObjectURL(link.href); link.remove(); }, 1000);
}

// ---- small DOM helpers ------------------------------------------------------------------------------

function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k.startsWith("on")) node.addEventListener(k.slice(2), v);
    else node.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children.flat()) if (c !== undefined && c !== null) node.append(c instanceof Node ? c : String(c));
  return node;
}

function progressBar(job) {
  const pct = Math.round(100 * (job.progress || 0));
  const bar = el("span", { class: "progress", title: pct + " %" }, el("span", { style: "width:" + pct + "%" }));
  const eta = job.status === "running" && job.eta_seconds !== undefined ? " · " + duration(job.eta_seconds) + " left" : "";
  return [bar, " " + pct + " %" + eta];
}

function duration(s) {
  if (s < 90) return Math.round(s) + " s";
  if (s < 5400) return Math.round(s / 60) + " min";
  return (s / 3600).toFixed(1) + " h";
}

function statusCell(status) { return el("span", { class: "status status-" + status }, status); }
// A job's warnings (criteria the run missed) as a mark whose tooltip lists them.
function warningMark(warnings) {
  if (!warnings || !warnings.length) return null;
  return el("span", { class: "warning", title: warnings.join("\n") }, " ⚠ " + warnings.length);
}
// The registry's experiments by name ({headline, curve_columns, ...}), fetched once.
let registryCache = null;
async function experiments() {
  if (!registryCache) {
    const registry = await getJson("/v1/experiments");
    registryCache = Object.fromEntries(registry.experiments.map((e) => [e.name, e]));
  }
  return registryCache;
}
function headlineOf(registry, name) { return registry[name] ? registry[name].headline : null; }
// A stored (SI) value as an axis of the headline reads it: in natural units when `at` (the spec, or a
// lookup) gives the scale's per_field, else in SI units.
function reading(axis, value, at) {
  let scale = axis.natural;
  const per = scale.per_field ? at(scale.per_field) : 1;
  if (!(per > 0)) scale = axis.si;
  const v = value * scale.factor / (scale.per_field && scale === axis.natural ? per : 1);
  return fmt(v) + (scale.unit === "-" ? "" : " " + scale.unit);
}
// A running job's latest row: its headline's x and first series now.
function latestText(latest, headline, at = () => undefined) {
  if (!latest || !headline) return "";
  const parts = [];
  if (latest[headline.x.column] !== undefined) parts.push(headline.x.label + " " + reading(headline.x, latest[headline.x.column], at));
  const first = headline.series[0];
  if (first && latest[first.column] !== undefined) parts.push(first.label + " " + reading(headline.y, latest[first.column], at));
  return parts.join(", ");
}
// The headline's key values of a summary (or a sweep's job item, which holds the same groups).
function keyValues(headline, summary, at) {
  if (!headline || !summary) return [];
  return headline.values.filter((v) => missingReason(summary, v) !== undefined || typeof lookup(summary, v.key) === "number").map((v) => {
    const missing = missingReason(summary, v);
    if (missing !== undefined) return v.label + ": " + missing;
    const where = v.at_x && typeof lookup(summary, v.at_x) === "number" ? " at " + reading(headline.x, lookup(summary, v.at_x), at) : "";
    return v.label + " " + fmt(lookup(summary, v.key)) + (v.unit === "-" ? "" : " " + v.unit) + where;
  });
}
// When a key value's status group says it was not found (a crystal that never yields has no first yield), the reason
// it gives ("none to 1 % strain: ..."); undefined when it was found or may not be missing.
function missingReason(summary, v) {
  const group = v.status ? lookup(summary, v.status) : undefined;
  if (!group || typeof group !== "object" || group.found !== false) return undefined;
  return typeof group.reason === "string" ? group.reason : "none";
}
// A spec field's allowed range as it is: "(0, 0.5]" when the lower bound itself is not allowed, the upper bound
// another field's value when it is one ("[0, loading.max_strain]"), "each in" for a list's values; "" for none.
function rangeText(f) {
  if (f.minimum === undefined) return "";
  const upper = f.maximum !== undefined ? f.maximum : f.maximum_is;
  const range = (f.exclusive_minimum ? "(" : "[") + f.minimum + ", " + (upper !== undefined ? upper : "∞") + "]";
  return (f.type.startsWith("array") ? " each in " : " ") + range;
}
// A summary list of groups (a crystal's load-unload cycles, say) as a table: a column per field.
function summaryTable(title, rows) {
  const flat = rows.map((r) => Object.fromEntries(Object.entries(r).filter(([, v]) => typeof v !== "object")));
  const keys = [...new Set(flat.flatMap((r) => Object.keys(r)))];
  return el("section", { class: "summary-table" }, el("h3", {}, title),
    el("table", {}, el("tr", {}, keys.map((k) => el("th", {}, k))),
      ...flat.map((r) => el("tr", {}, keys.map((k) => el("td", { class: typeof r[k] === "number" ? "num" : "" },
        typeof r[k] === "number" ? fmt(r[k], 4) : String(r[k] ?? "")))))));
}
// A snapshot's slip bands (docs/api.md): plane and direction by their indices, slip, dilation and extent.
function bandTable(bands) {
  if (!Array.isArray(bands)) return null;
  const title = el("h3", {}, "Slip bands (interfaces sliding more than twice the mean)");
  if (!bands.length) return el("section", { class: "summary-table" }, title, el("p", { class: "hint" }, "none: no band of sliding interfaces"));
  const mm = (m) => fmt(1e3 * m, 3);
  return el("section", { class: "summary-table" }, title,
    el("table", { id: "slip-band-table" },
      el("tr", {}, ["plane", "off plane (°)", "slip (mm)", "direction", "off direction (°)", "dilation (°)", "extent (mm)", "interfaces"].map((h) => el("th", {}, h))),
      ...bands.map((b) => el("tr", { class: "slip-band" },
        el("td", {}, b.plane), el("td", { class: "num" }, fmt(b.angle_to_plane, 2)), el("td", { class: "num" }, mm(b.slip)),
        el("td", {}, b.direction), el("td", { class: "num" }, fmt(b.direction_angle, 2)), el("td", { class: "num" }, fmt(b.dilation_angle, 2)),
        el("td", { class: "num" }, mm(b.extent)), el("td", { class: "num" }, String(b.interfaces))))));
}
function when(ms) { return ms ? new Date(ms).toLocaleString() : ""; }
function fmt(x, digits = 3) { return typeof x === "number" ? Number(x.toPrecision(digits)).toString() : ""; }
// replaceChildren, skipping null and undefined (which the DOM would write as text).
function fill(node, ...children) { node.replaceChildren(...children.flat().filter((c) => c !== null && c !== undefined)); }
function setMain(...children) { fill(document.getElementById("main"), ...children); }
function live(job) { return job.status === "queued" || job.status === "running"; }

// ---- views ------------------------------------------------------------------------------------------

async function listView() {
  const jobsTable = el("table", { id: "jobs" });
  const sweepsTable = el("table", { id: "sweeps" });
  setMain(el("h1", {}, "Jobs"), jobsTable, el("h2", {}, "Sweeps"), sweepsTable);
  const refresh = async () => {
    const [jobs, sweeps, registry] = await Promise.all([getJson("/v1/jobs?limit=100"), getJson("/v1/sweeps?limit=50"), experiments()]);
    fill(jobsTable, el("tr", {}, ["id", "label", "experiment", "status", "progress", "owner", "submitted"].map((h) => el("th", {}, h))),
      ...jobs.jobs.map((j) => el("tr", { "data-id": j.id },
        el("td", { class: "num" }, el("a", { href: "#/jobs/" + j.id }, j.id)),
        el("td", {}, el("a", { href: "#/jobs/" + j.id }, j.label || "(no label)"),
          j.sweep_id ? el("span", { class: "hint" }, " · ", el("a", { href: "#/sweeps/" + j.sweep_id }, "sweep " + j.sweep_id)) : null),
        el("td", {}, j.experiment), el("td", { class: "status-cell" }, statusCell(j.status), warningMark(j.warnings)),
        el("td", {}, progressBar(j), j.latest ? el("div", { class: "hint" }, latestText(j.latest, headlineOf(registry, j.experiment))) : null),
        el("td", {}, j.owner || ""), el("td", {}, when(j.created_ms)))));
    if (!jobs.jobs.length) jobsTable.append(el("tr", {}, el("td", { colspan: 7 }, "No jobs yet: ", el("a", { href: "#/submit" }, "submit one"))));
    fill(sweepsTable, el("tr", {}, ["id", "label", "varied", "owner", "created"].map((h) => el("th", {}, h))),
      ...sweeps.sweeps.map((s) => el("tr", { "data-id": s.id },
        el("td", { class: "num" }, el("a", { href: "#/sweeps/" + s.id }, s.id)),
        el("td", {}, el("a", { href: "#/sweeps/" + s.id }, s.label || "(no label)")),
        el("td", {}, Object.entries(s.vary || {}).map(([k, v]) => k + " = " + JSON.stringify(v)).join("; ")),
        el("td", {}, s.owner || ""), el("td", {}, when(s.created_ms)))));
    return jobs.jobs.some(live);
  };
  return refresh;
}

async function jobView(id) {
  const head = el("div", { id: "job-head" });
  const curve = el("div", { class: "picture", id: "curve" }, el("p", { class: "hint" }, "loading the curve…"));
  const snapshotPicture = el("div", { class: "picture", id: "snapshot" });
  const snapshotSelect = el("select", { id: "snapshot-index" });
  const fieldSelect = el("select", { id: "snapshot-field" },
    ["equivalent_strain", "gamma_max", "penetration_ratio", "displacement", "d2min", "misorientation"].map((f) => el("option", { value: f }, f)));
  const sliceInput = el("input", { id: "snapshot-slice", type: "number", min: 0, placeholder: "middle", style: "width:6em" });
  const snapshotDownloads = el("span", { class: "downloads" });
  // The snapshot's slip bands (summary or snapshot JSON) and its front face as DIC would see it.
  const bandsTable = el("div", { id: "slip-bands" });
  const dicPicture = el("div", { class: "picture", id: "dic" });
  const dicField = el("select", { id: "dic-field" },
    ["gamma_max", "exx", "ezz", "exz", "ux", "uz"].map((f) => el("option", { value: f }, f)));
  const dicStep = el("input", { id: "dic-step", type: "number", min: 0, step: "any", placeholder: "default", style: "width:7em" });
  const snapshots = el("section", { id: "snapshots", hidden: true }, el("h2", {}, "Snapshots"),
    el("div", { class: "controls" }, el("label", {}, "snapshot ", snapshotSelect), el("label", {}, "field ", fieldSelect),
      el("label", { title: "a layer of the crystal normal to y: {111} for the paper's crystal; the picture's caption names the planes" }, "layer ", sliceInput), snapshotDownloads),
    snapshotPicture, bandsTable,
    el("h3", {}, "Front face, as digital image correlation would see it"),
    el("div", { class: "controls" }, el("label", {}, "field ", dicField),
      el("label", { title: "the grid step in metres (default: half the grain spacing)" }, "grid step (m) ", dicStep)),
    dicPicture);
  const downloads = el("p", { class: "downloads" },
    el("a", { href: "#", onclick: (e) => { e.preventDefault(); download(`/v1/jobs/${id}/curve?format=csv`, `job${id}_curve.csv`); } }, "curve.csv"),
    el("a", { href: "#", onclick: (e) => { e.preventDefault(); download(`/v1/jobs/${id}/curve.svg`, `job${id}_curve.svg`); } }, "curve.svg"),
    el("a", { href: "#", onclick: (e) => { e.preventDefault(); download(`/v1/jobs/${id}/archive`, `job_${id}.tar`); } }, "everything (.tar)"));
  // The curve as its experiment's headline draws it, or one column; in natural units or SI.
  const columnSelect = el("select", { id: "curve-y" }, el("option", { value: "" }, "headline"));
  const unitsSelect = el("select", { id: "curve-units" }, el("option", { value: "natural" }, "natural"), el("option", { value: "si" }, "SI"));
  const curveControls = el("div", { class: "controls" }, el("label", {}, "show ", columnSelect), el("label", {}, "units ", unitsSelect));
  const tables = el("div", { id: "summary-tables" });
  const curvePath = () => `/v1/jobs/${id}/curve.svg?units=${unitsSelect.value}` + (columnSelect.value ? "&y=" + encodeURIComponent(columnSelect.value) : "");
  let lastStatus = null;
  for (const control of [columnSelect, unitsSelect]) control.addEventListener("change", () => { if (lastStatus !== "queued") picture(curvePath(), curve); });
  setMain(head, el("h2", {}, "Curve"), curveControls, curve, downloads, tables, snapshots);

  const showSnapshot = () => {
    const k = snapshotSelect.value;
    if (k === "") return;
    const slice = sliceInput.value === "" ? "" : "&slice=" + encodeURIComponent(sliceInput.value);
    picture(`/v1/jobs/${id}/snapshots/${k}.svg?field=${fieldSelect.value}${slice}`, snapshotPicture);
    const step = dicStep.value === "" ? "" : "&step=" + encodeURIComponent(dicStep.value);
    picture(`/v1/jobs/${id}/snapshots/${k}/dic.svg?field=${dicField.value}${step}`, dicPicture);
    const files = { vtk_interfaces: "interfaces.vtk", contacts_vtk: "contacts.vtk", contacts_dump: "contacts.dump",
      mesh_vtk: "meshes.vtk", dic_csv: "dic.csv", dic_vtk: "dic.vtk" };
    fill(snapshotDownloads, "download: ", ...["json", "dump", "vtk", "vtk_interfaces", "contacts_vtk", "contacts_dump", "mesh_vtk", "dic_csv", "dic_vtk"].map((f) =>
      el("a", { href: "#", onclick: (e) => { e.preventDefault(); download(`/v1/jobs/${id}/snapshots/${k}?format=${f}${f.startsWith("dic") ? step : ""}`,
        `job${id}_snapshot_${k}.${files[f] || f}`); } }, f)));
    showBands(k);
  };
  // A finished job's summary lists each snapshot's bands; a running one's come from the snapshot itself.
  let summarySnapshots = null;
  const bandsOf = {};  // a running job's snapshots' bands, fetched once each
  const showBands = async (k) => {
    let bands = summarySnapshots && summarySnapshots[k] ? summarySnapshots[k].slip_bands : bandsOf[k];
    if (bands === undefined) {
      try { bands = bandsOf[k] = (await getJson(`/v1/jobs/${id}/snapshots/${k}`)).slip_bands; } catch (e) { bands = undefined; }
    }
    if (snapshotSelect.value !== String(k)) return;  // another snapshot was chosen meanwhile
    fill(bandsTable, bandTable(bands));
  };
  for (const control of [snapshotSelect, fieldSelect, sliceInput, dicField, dicStep]) control.addEventListener("change", showSnapshot);

  let known = -1;
  const refresh = async () => {
    const [job, registry] = await Promise.all([getJson("/v1/jobs/" + id), experiments()]);
    const warnings = job.warnings || [];
    const headline = headlineOf(registry, job.experiment);
    const at = (field) => lookup(job.spec, field);
    if (columnSelect.options.length === 1 && registry[job.experiment])
      columnSelect.append(...registry[job.experiment].curve_columns.map((c) => el("option", { value: c.name }, c.name + " (" + c.unit + ")")));
    lastStatus = job.status;
    summarySnapshots = job.summary && Array.isArray(job.summary.snapshots) ? job.summary.snapshots : null;
    fill(head, 
      el("h1", {}, "Job " + job.id + ": " + (job.label || job.experiment)),
      el("p", {}, statusCell(job.status), "  ", progressBar(job),
        live(job) ? el("button", { style: "margin-left:1em", onclick: async () => { const r = await sendJson("POST", `/v1/jobs/${id}/cancel`); if (r.status >= 400) alert(r.body.error ? r.body.error.message : "HTTP " + r.status); } }, "Cancel") : null),
      job.latest ? el("p", { id: "latest" }, "now: " + latestText(job.latest, headline, at)) : null,
      job.error ? el("p", { class: "error" }, job.error) : null,
      ...warnings.map((w) => el("p", {}, el("span", { class: "warning" }, "⚠ " + w))),
      el("p", { class: "hint" }, job.experiment, job.owner ? " · owner " + job.owner : "",
        job.sweep_id ? [" · ", el("a", { href: "#/sweeps/" + job.sweep_id }, "sweep " + job.sweep_id)] : "",
        // On a Slurm cluster: which Slurm job, and Slurm's word on it (e.g. PENDING (Resources)).
        job.slurm_job_id ? " · Slurm job " + job.slurm_job_id + (job.slurm_state ? ": " + job.slurm_state : "") : "",
        " · engine ", job.engine_version, " · submitted ", when(job.created_ms)),
      keyValues(headline, job.summary, at).length ? el("p", { id: "key-values" }, keyValues(headline, job.summary, at).join("; ")) : null);
    fill(tables, ...(headline && job.summary ? headline.tables : [])
      .filter((t) => Array.isArray(job.summary[t.key]) && job.summary[t.key].length)
      .map((t) => summaryTable(t.title, job.summary[t.key])));
    if (job.status !== "queued") await picture(curvePath(), curve);
    else fill(curve, el("p", { class: "hint" }, "queued: the curve appears when it starts"));
    const list = (await getJson(`/v1/jobs/${id}/snapshots`)).snapshots;
    if (list.length !== known) {
      const chosen = snapshotSelect.value;
      fill(snapshotSelect, ...list.map((s) => el("option", { value: s.index }, s.index + " (strain " + fmt(100 * s.strain) + " %)")));
      snapshots.hidden = list.length === 0;
      if (list.length) {
        snapshotSelect.value = chosen !== "" && chosen < list.length ? chosen : String(list[list.length - 1].index);
        showSnapshot();
      }
      known = list.length;
    }
    return live(job);
  };
  return refresh;
}

async function sweepView(id) {
  const head = el("div", { id: "sweep-head" });
  const curves = el("div", { class: "picture", id: "curves" });
  const table = el("table", { id: "sweep-jobs" });
  setMain(head, curves, el("h2", {}, "Jobs"), table);
  const refresh = async () => {
    const [sweep, registry] = await Promise.all([getJson("/v1/sweeps/" + id), experiments()]);
    const keys = Object.keys(sweep.vary || {});
    // A spec without "experiment" is of the first registered one (the registry's order is kept).
    const experiment = (sweep.spec && sweep.spec.experiment) || Object.keys(registry)[0] || "";
    const headline = headlineOf(registry, experiment) || { x: null, series: [], values: [] };
    // A job's spec field: its own varied value, else the base spec's.
    const at = (j) => (field) => (j.values && j.values[field] !== undefined ? j.values[field] : lookup(sweep.spec, field));
    const anyLive = sweep.jobs.some(live);
    fill(head, el("h1", {}, "Sweep " + sweep.id + (sweep.label ? ": " + sweep.label : ""),
      el("span", { class: "hint" }, " varying " + Object.keys(sweep.vary || {}).join(", "))),
      el("p", {}, Object.entries(sweep.counts).map(([s, n]) => n + " " + s).join(", "),
        anyLive ? el("button", { style: "margin-left:1em", onclick: async () => { const r = await sendJson("POST", `/v1/sweeps/${id}/cancel`); if (r.status >= 400) alert(r.body.error ? r.body.error.message : "HTTP " + r.status); } }, "Cancel the rest") : null));
    await picture(`/v1/sweeps/${id}/curves.svg`, curves);
    fill(table, el("tr", {}, ["job", ...keys, "status", "progress", ...headline.values.map((v) => v.label + (v.unit === "-" ? "" : " (" + v.unit + ")"))].map((h) => el("th", {}, h))),
      ...sweep.jobs.map((j) => el("tr", { "data-id": j.id },
        el("td", { class: "num" }, el("a", { href: "#/jobs/" + j.id }, j.id)),
        ...keys.map((k) => el("td", { class: "num" }, JSON.stringify(j.values[k]))),
        el("td", {}, statusCell(j.status), warningMark(j.warnings), j.error ? el("div", { class: "error" }, j.error) : null),
        el("td", {}, progressBar(j), j.latest ? el("div", { class: "hint" }, latestText(j.latest, headline.x ? headline : null, at(j))) : null),
        ...headline.values.map((v) => missingReason(j, v) !== undefined
          ? el("td", { class: "hint", title: missingReason(j, v) }, "none", el("div", { class: "hint" }, missingReason(j, v)))
          : el("td", { class: "num" }, typeof lookup(j, v.key) === "number"
          ? fmt(lookup(j, v.key)) + (v.at_x && typeof lookup(j, v.at_x) === "number" ? " at " + reading(headline.x, lookup(j, v.at_x), at(j)) : "")
          : "")))));
    return anyLive;
  };
  return refresh;
}

// The nested spec value at a dotted key, or undefined.
function lookup(spec, dotted) {
  return dotted.split(".").reduce((o, k) => (o && typeof o === "object" ? o[k] : undefined), spec);
}

async function submitView() {
  const [registry, examples] = await Promise.all([getJson("/v1/experiments"), getJson("/v1/examples")]);
  const experimentSelect = el("select", { id: "experiment" }, registry.experiments.map((e) => el("option", { value: e.name }, e.name)));
  const exampleSelect = el("select", { id: "example" });
  const form = el("form", { class: "spec", id: "spec-form", novalidate: true });
  const vary = el("textarea", { id: "vary", rows: 3, cols: 60, placeholder: "loading.confining_pressure=10e3,30e3,60e3" });
  const zip = el("input", { type: "checkbox", id: "zip" });
  const message = el("p", { id: "submit-message" });
  const cost = el("p", { id: "submit-cost" });
  setMain(el("h1", {}, "Submit an experiment"),
    el("div", { class: "controls" }, el("label", {}, "experiment ", experimentSelect), el("label", {}, "start from ", exampleSelect)),
    form,
    el("h2", {}, "Sweep (optional)"),
    el("p", { class: "hint" }, "One line per varied field, as granulab sweep --vary takes it: dotted.key=value1,value2,… with each value JSON (10e3, \"text\", a list [1,1,0]) or plain text, commas inside [ ] { } \"…\" belonging to the value, e.g. loading.axis=[1,1,0],[1,1,1]. Every combination runs, or the lists are paired with ‘zip’."),
    vary, el("div", {}, el("label", {}, zip, " zip the lists")),
    cost, el("p", {}, el("button", { id: "submit", type: "button", onclick: () => submit() }, "Submit")), message);

  let fields = [];
  const build = () => {
    const experiment = registry.experiments.find((e) => e.name === experimentSelect.value);
    const example = examples.examples.find((x) => x.name === exampleSelect.value);
    // The registry lists job fields (run.threads) before the experiment's: keep each section together.
    const sectionOf = (f) => (f.field.includes(".") ? f.field.split(".")[0] : "");
    const order = [...new Set(experiment.fields.map(sectionOf))];
    fields = experiment.fields.filter((f) => f.field !== "experiment" && !f.field.includes("[]."))
      .sort((a, b) => order.indexOf(sectionOf(a)) - order.indexOf(sectionOf(b)));
    const rows = [];
    let section = "";
    for (const f of fields) {
      const top = f.field.includes(".") ? f.field.split(".")[0] : "";
      if (top !== section) { section = top; rows.push(el("div", { class: "section" }, section)); }
      const value = example ? lookup(example.spec, f.field) : undefined;
      const shown = value !== undefined ? value : f.default;
      const text = typeof shown === "object" ? JSON.stringify(shown) : String(shown);
      const unit = f.unit && f.unit !== "-" ? " (" + f.unit + ")" : "";
      const attrs = { id: "f-" + f.field, name: f.field, "data-default": JSON.stringify(f.default),
        "data-default-text": value !== undefined ? "" : text };
      // A field with a list of values is a menu of them (the shown value selected); any other a text box.
      const input = f.choices
        ? el("select", attrs, [...new Set([...f.choices, text])].map((c) => el("option", { value: c, selected: c === text }, c)))
        : el("input", { ...attrs, value: text });
      rows.push(el("label", { for: "f-" + f.field }, f.field), input,
        el("span", { class: "meaning" }, f.meaning + unit + rangeText(f)),
        el("div", { class: "field-error", id: "e-" + f.field, hidden: true }));
    }
    fill(form, ...rows);
  };
  const fillExamples = () => {
    const list = examples.examples.filter((x) => (x.spec.experiment || "two_cube_sliding") === experimentSelect.value);
    fill(exampleSelect, el("option", { value: "" }, "the defaults"), ...list.map((x) => el("option", { value: x.name }, x.name + ": " + (x.spec.label || ""))));
    if (list.length) exampleSelect.value = list[0].name;
    build();
  };
  experimentSelect.addEventListener("change", fillExamples);
  exampleSelect.addEventListener("change", build);
  fillExamples();

  const showError = (field, text) => {
    const key = (field || "").replace(/^spec\./, "").replace(/^vary\./, "");
    const holder = document.getElementById("e-" + key);
    const input = document.getElementById("f-" + key);
    if (holder && input) {
      holder.textContent = text;
      holder.hidden = false;
      input.classList.add("bad");
      input.scrollIntoView({ block: "center" });
    }
    fill(message, el("span", { class: "error" }, text));
  };

  async function submit() {
    const button = document.getElementById("submit");
    if (button.disabled) return;  // one submission at a time: a double click makes one job
    button.disabled = true;
    try {
      await send();
    } catch (e) {
      showError("", e.message);
    } finally {
      button.disabled = false;
    }
  }

  // The form as a spec and the sweep's lists, or the field that is wrong.
  function readForm() {
    const spec = { experiment: experimentSelect.value };
    for (const f of fields) {
      const input = document.getElementById("f-" + f.field);
      let value = input.value.trim();
      if (value === "" && f.type !== "string") continue;  // left empty: the default
      // Left at the shown default: let the server fill it, since some defaults follow other fields
      // (loading.rate_number = 1.5 p0/E; loading.wall_friction = material.friction).
      if (input.dataset.defaultText && value === input.dataset.defaultText) continue;
      if (f.type === "number" || f.type === "integer") value = Number(value);
      else if (f.type.startsWith("array")) {
        try { value = JSON.parse(value); } catch (e) { return { error: [f.field, f.field + ": not a JSON list"] }; }
      }
      if (typeof value === "number" && Number.isNaN(value)) return { error: [f.field, f.field + ": not a number"] };
      setDotted(spec, f.field, value);
    }
    const varied = {};
    for (const line of vary.value.split("\n").map((l) => l.trim()).filter(Boolean)) {
      const eq = line.indexOf("=");
      if (eq < 0) return { error: ["", "sweep line '" + line + "' has no '=' (e.g. loading.axis=[1,1,0],[1,1,1])"] };
      const key = line.slice(0, eq).trim();
      if (!/^\w+(\.\w+)*$/.test(key)) return { error: ["", "sweep line '" + line + "': '" + key + "' is not a dotted field"] };
      if (Object.prototype.hasOwnProperty.call(varied, key)) return { error: ["", "sweep line '" + line + "': " + key + " is varied twice"] };
      const values = sweepValues(line.slice(eq + 1));
      if (typeof values === "string") return { error: ["", "sweep line '" + line + "': " + values + " (e.g. loading.axis=[1,1,0],[1,1,1])"] };
      varied[key] = values;
    }
    const lengths = Object.entries(varied).map(([k, v]) => k + " has " + v.length);
    if (zip.checked && new Set(Object.values(varied).map((v) => v.length)).size > 1)
      return { error: ["", "zip pairs the lists value by value, so they must be as long as each other: " + lengths.join(", ")] };
    return { spec, varied, sweep: Object.keys(varied).length > 0 };
  }

  // The cost of what the form would submit: a dry run of each job (a sweep's combinations, at most 50),
  // shown as the spec changes; `last` is what the Submit button warns with.
  let last = null, pending = null;
  async function estimate() {
    const form = readForm();
    if (form.error) return fill(cost, el("span", { class: "hint" }, "cost: " + form.error[1]));
    const specs = jobsOf(form.spec, form.varied, zip.checked);
    if (specs.length > 50) return fill(cost, el("span", { class: "hint" }, specs.length + " jobs: too many to estimate here"));
    const answers = await Promise.all(specs.map((s) => sendJson("POST", "/v1/jobs?dry_run=true", s)));
    const bad = answers.find((a) => a.status >= 400);
    if (bad) {
      last = null;
      const e = bad.body.error || {};
      return fill(cost, el("span", { class: "error" }, "not accepted: " + (e.message || "HTTP " + bad.status)));
    }
    const seconds = answers.reduce((t, a) => t + a.body.expected_seconds, 0);
    const over = answers.find((a) => a.body.over_budget);
    const one = answers[0].body;
    last = { seconds, jobs: answers.length };
    const what = answers.length > 1
      ? answers.length + " jobs, about " + duration(seconds) + " of compute in all (one after another on a worker)"
      : "about " + duration(seconds) + " once started (" + fmt(one.steps) + " steps: " +
        one.phases.map((p) => p.name + " " + fmt(p.steps, 2)).join(", ") + "), " + fmt(one.memory_bytes / 1e6, 2) + " MB";
    fill(cost, el("span", { class: seconds > LONG_JOB_SECONDS ? "warning" : "hint" }, "Expected: " + what + " on " +
      one.threads + " thread(s); " + one.queued_ahead + " queued ahead. Speed: " + one.rate_basis + "."),
      answers.length === 1 && one.yield_estimate ? el("div", { class: "hint", id: "submit-yield" }, one.yield_estimate.text + ".") : null,
      over ? el("div", { class: "error" }, "over budget: " + over.body.over_budget) : null);
  }
  const scheduleEstimate = () => { clearTimeout(pending); pending = setTimeout(() => estimate().catch((e) => fill(cost, el("span", { class: "error" }, e.message))), 400); };
  form.addEventListener("input", scheduleEstimate);
  vary.addEventListener("input", scheduleEstimate);
  zip.addEventListener("change", scheduleEstimate);
  experimentSelect.addEventListener("change", scheduleEstimate);
  exampleSelect.addEventListener("change", scheduleEstimate);
  scheduleEstimate();

  async function send() {
    for (const e of form.querySelectorAll(".field-error")) e.hidden = true;
    for (const e of form.querySelectorAll("input.bad")) e.classList.remove("bad");
    message.textContent = "";
    const { spec, varied, sweep, error } = readForm();
    if (error) return showError(error[0], error[1]);
    await estimate().catch(() => {});
    if (last && last.seconds > LONG_JOB_SECONDS &&
        !window.confirm("This is expected to take about " + duration(last.seconds) + (last.jobs > 1 ? " for " + last.jobs + " jobs" : "") + ". Submit it?"))
      return fill(message, el("span", { class: "hint" }, "not submitted"));
    const answer = sweep
      ? await sendJson("POST", "/v1/sweeps", { spec, vary: varied, mode: zip.checked ? "zip" : "product", label: spec.label || "" })
      : await sendJson("POST", "/v1/jobs", spec);
    if (answer.status >= 400) {
      const error = answer.body.error || { field: "", message: "HTTP " + answer.status };
      return showError(error.field, error.message);
    }
    location.hash = sweep ? "#/sweeps/" + answer.body.id : "#/jobs/" + answer.body.id;
  }
  return null;
}

// Longer than this (s), the submit form asks before queueing.
const LONG_JOB_SECONDS = 600;

function setDotted(spec, dotted, value) {
  const path = dotted.split(".");
  let at = spec;
  for (const k of path.slice(0, -1)) at = at[k] = at[k] && typeof at[k] === "object" ? at[k] : {};
  at[path[path.length - 1]] = value;
}

// A sweep line's values, as `granulab sweep --vary` reads them (clients/cli/vary_option.h): split at the commas
// outside [ ], { } and "...", each JSON or else plain text; or what is wrong, as a string.
function sweepValues(text) {
  const items = [], closers = [];
  let quoted = false, escaped = false, start = 0;
  for (let i = 0; i < text.length; ++i) {
    const c = text[i];
    if (quoted) {
      if (escaped) escaped = false;
      else if (c === "\\") escaped = true;
      else if (c === '"') quoted = false;
    } else if (c === '"') quoted = true;
    else if (c === "[" || c === "{") closers.push(c === "[" ? "]" : "}");
    else if (c === "]" || c === "}") {
      const due = closers.pop();
      if (due !== c) return "a '" + c + "' " + (due ? "where a '" + due + "' was due" : "that closes nothing");
    } else if (c === "," && !closers.length) {
      items.push(text.slice(start, i));
      start = i + 1;
    }
  }
  if (quoted) return "a '\"' is never closed";
  if (closers.length) return "a '" + (closers.pop() === "]" ? "[" : "{") + "' is never closed";
  items.push(text.slice(start));
  const values = [];
  for (const [n, raw] of items.entries()) {
    const item = raw.trim(), which = "value " + (n + 1) + " of " + items.length;
    if (!item) return which + " is empty";
    let parsed;
    try { parsed = JSON.parse(item); } catch (e) { parsed = undefined; }
    if ("[{\"".includes(item[0])) {
      if (parsed === undefined) return which + ", " + item + ", is not JSON";
      values.push(parsed);
    } else if (/[\[\]{}"]/.test(item)) return which + ", " + item + ", is text with brackets or quotes in it";
    else values.push(parsed === undefined ? item : parsed);
  }
  return values;
}

// The specs of a sweep: every combination of the lists (or the lists paired, zip), as the server makes them.
function jobsOf(spec, varied, zip) {
  const keys = Object.keys(varied);
  if (!keys.length) return [spec];
  let combos = [];
  if (zip) {
    const n = Math.min(...keys.map((k) => varied[k].length));
    for (let i = 0; i < n; ++i) combos.push(keys.map((k) => varied[k][i]));
  } else {
    combos = [[]];
    for (const k of keys) combos = combos.flatMap((c) => varied[k].map((v) => [...c, v]));
  }
  return combos.map((values) => {
    const one = JSON.parse(JSON.stringify(spec));
    keys.forEach((k, i) => setDotted(one, k, values[i]));
    return one;
  });
}

// ---- routing ----------------------------------------------------------------------------------------

async function route() {
  clearTimeout(timer);
  ++views;
  const hash = location.hash || "#/";
  let match, refresh = null;
  try {
    if ((match = hash.match(/^#\/jobs\/(\d+)$/))) refresh = await jobView(match[1]);
    else if ((match = hash.match(/^#\/sweeps\/(\d+)$/))) refresh = await sweepView(match[1]);
    else if (hash === "#/submit") refresh = await submitView();
    else refresh = await listView();
  } catch (e) {
    return setMain(el("p", { class: "error" }, e.message));
  }
  const current = hash, generation = ++views;
  // Refresh while anything shown is queued or running; the list keeps polling (new jobs may come). An error
  // (a daemon restarting, a missing token) shows once and polling goes on, slower, until it clears.
  let failures = 0;
  const tick = async () => {
    if (generation !== views) return;  // another view (or the same one again) took over
    let again = true;
    try {
      again = await refresh();
      failures = 0;
      showViewError(null);
    } catch (e) {
      failures += 1;
      showViewError(e.message);
    }
    if (generation !== views) return;
    if (again || failures || current === "#/" || current === "")
      timer = setTimeout(tick, REFRESH_MS * Math.min(8, 1 + failures));
  };
  if (refresh) tick();
}

let views = 0;  // the current view's number: a polling loop of an older one stops

// One error line above the view, replaced (not piled up) while the error lasts, removed when it clears.
function showViewError(message) {
  let line = document.getElementById("view-error");
  if (!message) return line && line.remove();
  if (!line) {
    line = el("p", { class: "error", id: "view-error" });
    document.getElementById("main").prepend(line);
  }
  line.textContent = message;
}

document.getElementById("token-form").addEventListener("submit", (e) => {
  e.preventDefault();
  localStorage.setItem("granulab_token", document.getElementById("token").value.trim());
  document.getElementById("token-bar").hidden = true;
  route();
});
window.addEventListener("hashchange", route);
fetch("/v1/health").then((r) => r.json()).then((h) => {
  document.getElementById("server").textContent = "engine " + h.engine_version + " · " + h.running + " running, " + h.queued + " queued";
}).catch(() => {});
route();
