// One job: its state, progress, previews (the combined image and one tile per partition or type
// layer), partition table, parameters and statistics, fed by the job's server-sent events
// (GET /api/jobs/ID/events); cancel and downloads.
"use strict";

const jobId = new URLSearchParams(window.location.search).get("id") || "";
const errorSeries = new Map();  // plot: name -> [[elapsed seconds, relative RMSE estimate]]
let frames = 0;

let terminalSeen = false;

function setState(job) {
  // A terminal state is final: an answer that was in flight when the events brought it (the
  // cancel request's, which still says RENDERING) must not take the page back.
  if (terminalSeen && !isTerminal(job.state)) return;
  terminalSeen = isTerminal(job.state);
  const state = stateName(job.state);
  const badge = document.getElementById("state");
  badge.textContent = state;
  badge.className = "state " + state;
  document.getElementById("error").textContent = job.error || "";
  document.getElementById("note").textContent = job.note || "";
  document.getElementById("cancel").disabled = isTerminal(job.state);
  for (const [id, file] of [["download-exr", "result.exr"], ["download-png", "preview.png"]]) {
    const link = document.getElementById(id);
    link.href = `/api/jobs/${encodeURIComponent(jobId)}/${file}`;
    link.classList.toggle("disabled", state !== "DONE");
  }
  if (state === "DONE") setProgressBar(1);
  showParameters(job.spec || {});
  showStatistics(job.stats || {});
  if (job.progress) showProgress(job.progress);
}

function setProgressBar(fraction) {
  document.getElementById("progress-bar").style.width = (100 * fraction) + "%";
}

function showProgress(progress) {
  setProgressBar(progressFraction(progress));
  const parts = [progress.phase || ""];
  if (progress.total) parts.push(`${formatNumber(progress.done)} / ${formatNumber(progress.total)} ${progress.unit || ""}`);
  if (progress.rate_per_second) parts.push(formatRate(progress));
  if (progress.elapsed_seconds) parts.push(formatDuration(progress.elapsed_seconds) + " elapsed");
  if (progress.eta_seconds > 0) parts.push("ETA " + formatDuration(progress.eta_seconds));
  document.getElementById("progress-text").textContent = parts.filter(Boolean).join(" · ");
  if ((progress.partitions || []).length) showPartitions(progress.partitions);
  // The phase's own statistics: acceptance per mutation type, mutations, the error estimate.
  const live = Object.entries(progress.values || {}).sort().map(([k, v]) => [k, formatNumber(v)]);
  document.querySelector("#live tbody").replaceChildren(...keyValueRows(live));
  recordError(progress);
}

function showPartitions(partitions) {
  partitionTypes = partitions.map((p) => p.type);
  const rows = partitions.map((p) => el("tr", {},
    el("td", { text: p.type }), el("td", { text: formatNumber(p.p) }),
    el("td", { text: formatNumber(p.b) }),
    el("td", { text: (p.estimator || "chains") + (p.move ? ` (${p.move})` : "") }),
    el("td", { text: formatNumber(p.acceptance) })));
  document.querySelector("#partitions tbody").replaceChildren(...rows);
}

// The partitions' type strings (the latest partition table), to name their error curves.
let partitionTypes = [];

// The curve a progress value belongs to: "combined" for error_estimate, the partition's type
// for partition_<g>_error_estimate (partitioned, guided), none for any other value.
function errorCurveName(key) {
  if (key === "error_estimate") return "combined";
  const match = /^partition_(\d+)_error_estimate$/.exec(key);
  if (!match) return null;
  return partitionTypes[Number(match[1])] || `partition ${match[1]}`;
}

// The render's own error estimate (two halves of its samples or chains), when it reports one:
// the combined image's and each partition's.
function recordError(progress) {
  const values = progress.values || {};
  const t = Number(progress.elapsed_seconds || 0);
  for (const [key, value] of Object.entries(values)) {
    const name = errorCurveName(key);
    if (name === null) continue;
    if (!errorSeries.has(name)) errorSeries.set(name, []);
    errorSeries.get(name).push([t, Number(value)]);
  }
  const drawn = drawPlot(document.getElementById("plot"), errorSeries);
  document.getElementById("plot").dataset.points = String(drawn);
  document.getElementById("plot").dataset.curves =
    String([...errorSeries.values()].filter((data) => data.some(([, v]) => v > 0)).length);
  document.getElementById("plot-note").textContent = drawn
    ? "relative RMSE estimated from two halves of the render (samples or chains)"
    : "no error estimate reported yet";
}

function keyValueRows(entries) {
  return entries.map(([k, v]) => el("tr", {}, el("td", { text: k }), el("td", { text: v })));
}

function showParameters(spec) {
  const entries = [["algorithm", spec.algorithm || ""], ["scene", sceneText(spec)]];
  if (spec.budget) entries.push(["budget", `${formatNumber(spec.budget.amount)} ${(spec.budget.kind || "").replace("BUDGET_KIND_", "").toLowerCase()}`]);
  if (spec.label) entries.push(["label", spec.label]);
  for (const [name, value] of Object.entries(spec.parameters || {}).sort())
    entries.push([name, parameterText(value)]);
  document.querySelector("#parameters tbody").replaceChildren(...keyValueRows(entries));
}

function showStatistics(stats) {
  const entries = Object.entries(stats).sort().map(([k, v]) => [k, formatNumber(v)]);
  document.querySelector("#statistics tbody").replaceChildren(...keyValueRows(entries));
}

function showFrame(frame) {
  const layers = frame.layers || [];
  frames += 1;
  document.getElementById("frame-count").textContent =
    `frame ${frame.sequence || 0}${frame.final ? " (final)" : ""}`;
  document.getElementById("combined").dataset.frames = String(frames);
  const tiles = document.getElementById("tiles");
  for (const layer of layers) {
    const src = "data:image/png;base64," + layer.png;
    if (layer.name === "combined") {
      document.getElementById("combined").src = src;
      continue;
    }
    let figure = tiles.querySelector(`figure[data-layer="${CSS.escape(layer.name)}"]`);
    if (!figure) {
      figure = el("figure", { "data-layer": layer.name },
        el("img", { alt: layer.name }), el("figcaption", { text: layer.name }));
      tiles.append(figure);
    }
    const img = figure.querySelector("img");
    img.src = src;
    img.dataset.updates = String(Number(img.dataset.updates || 0) + 1);
  }
}

function watch() {
  const events = new EventSource(`/api/jobs/${encodeURIComponent(jobId)}/events`);
  events.addEventListener("state", (e) => setState(JSON.parse(e.data)));
  events.addEventListener("progress", (e) => showProgress(JSON.parse(e.data)));
  events.addEventListener("frame", (e) => showFrame(JSON.parse(e.data)));
  events.addEventListener("end", (e) => {
    document.getElementById("note").textContent = JSON.parse(e.data).error;
    events.close();
  });
  // The stream ends after the terminal state; EventSource would reconnect: stop it then.
  events.onerror = () => { if (terminalSeen) events.close(); };
}

async function start() {
  document.getElementById("job-id").textContent = jobId;
  document.title = "Partita — job " + jobId;
  document.getElementById("cancel").addEventListener("click", async () => {
    try {
      setState(await api.send("POST", `/api/jobs/${encodeURIComponent(jobId)}/cancel`));
    } catch (e) {
      document.getElementById("error").textContent = e.message;
    }
  });
  setState(await api.get(`/api/jobs/${encodeURIComponent(jobId)}`));
  watch();
}

start().catch((e) => { document.getElementById("error").textContent = e.message; });
