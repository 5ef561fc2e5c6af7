// The job list (refreshed every second) and the submit form, whose parameter fields come from
// the algorithms' declared parameters (GET /api/info).
"use strict";

let serverInfo = null;

function jobRow(job) {
  const progress = job.progress || {};
  const state = stateName(job.state);
  const bar = el("div", { class: "progress" }, el("div"));
  bar.firstChild.style.width = (100 * (state === "DONE" ? 1 : progressFraction(progress))) + "%";
  const spec = job.spec || {};
  const link = el("a", { href: "/job?id=" + encodeURIComponent(job.id), text: job.id });
  return el("tr", { "data-id": job.id },
    el("td", {}, link),
    el("td", {}, el("span", { class: "state " + state, text: state })),
    el("td", { text: spec.algorithm || "" }),
    el("td", { text: sceneText(spec) }),
    el("td", { text: spec.width && spec.height ? `${spec.width}x${spec.height}` : "" }),
    el("td", {}, bar),
    el("td", { text: isTerminal(job.state) ? "" : formatRate(progress) }),
    el("td", { text: isTerminal(job.state) ? "" : formatDuration(progress.eta_seconds) }),
    el("td", { text: formatTime(job.created_unix_ms) }),
    el("td", { text: formatTime(job.finished_unix_ms) }));
}

async function refreshJobs() {
  try {
    const answer = await api.get("/api/jobs");
    const jobs = (answer && answer.jobs) || [];
    const body = document.querySelector("#jobs tbody");
    body.replaceChildren(...jobs.slice().reverse().map(jobRow));
    document.getElementById("no-jobs").hidden = jobs.length > 0;
  } catch (e) {
    document.getElementById("no-jobs").textContent = "cannot list jobs: " + e.message;
  }
}

function parameterField(info) {
  const id = "param-" + info.name;
  const fallback = parameterText(info.default_value);
  let input;
  if (info.type === "bool") {
    input = el("select", { id }, el("option", { value: "", text: `default (${fallback || "off"})` }),
      el("option", { value: "true", text: "true" }), el("option", { value: "false", text: "false" }));
  } else if (info.type === "choice") {
    input = el("select", { id }, el("option", { value: "", text: `default (${fallback})` }),
      ...(info.choices || []).map((c) => el("option", { value: c, text: c })));
  } else {
    input = el("input", { id, type: ["int", "uint", "real"].includes(info.type) ? "number" : "text",
                          placeholder: fallback, step: "any" });
    if (info.min !== undefined) input.min = info.min;
    if (info.max !== undefined) input.max = info.max;
  }
  input.dataset.type = info.type;
  input.dataset.name = info.name;
  const title = (info.help || "") + (info.unit ? ` (${info.unit})` : "");
  return el("label", { title }, el("span", { text: info.name }), input);
}

function showParameters() {
  const name = document.getElementById("algorithm").value;
  const algorithm = serverInfo.algorithms.find((a) => a.name === name);
  document.getElementById("algorithm-help").textContent = algorithm.description || "";
  document.getElementById("budget-kind").value = algorithm.native_budget;
  const shown = algorithm.parameter_info || [];
  document.getElementById("parameters").replaceChildren(...shown.map(parameterField));
}

function parameterValue(input) {
  const text = input.value.trim();
  if (text === "") return null;
  switch (input.dataset.type) {
    case "bool": return { bool_value: text === "true" };
    case "int": return { int_value: text };
    case "uint": return { uint_value: text };
    case "real": return { real_value: Number(text) };
    case "rgb": {
      const [r, g, b] = text.split(/[ ,]+/).map(Number);
      return { rgb_value: { r, g, b } };
    }
    default: return { text_value: text };
  }
}

async function submit(event) {
  event.preventDefault();
  const errorText = document.getElementById("submit-error");
  errorText.textContent = "";
  const spec = {
    algorithm: document.getElementById("algorithm").value,
    budget: { kind: document.getElementById("budget-kind").value,
              amount: Number(document.getElementById("budget-amount").value) },
    label: document.getElementById("label").value,
    parameters: {},
  };
  const upload = document.getElementById("upload").files[0];
  if (upload) {
    try {
      const uploaded = await api.sendFile("/api/uploads", upload);
      spec.scene = { upload_id: uploaded.upload_id };
    } catch (e) {
      errorText.textContent = e.message;
      return;
    }
    spec.scene_file = upload.name;
  } else {
    spec.scene = { scene_name: document.getElementById("scene").value };
  }
  for (const input of document.querySelectorAll("#parameters [data-name]")) {
    const value = parameterValue(input);
    if (value) spec.parameters[input.dataset.name] = value;
  }
  try {
    const job = await api.send("POST", "/api/jobs", spec);
    window.location.href = "/job?id=" + encodeURIComponent(job.id);
  } catch (e) {
    errorText.textContent = e.message;
  }
}

async function start() {
  serverInfo = await api.get("/api/info");
  document.getElementById("server").textContent =
    `partitad ${serverInfo.version}, ${serverInfo.threads} threads, ` +
    `${serverInfo.max_concurrent_jobs} jobs at once`;
  const scenes = (await api.get("/api/scenes")).scenes || [];
  document.getElementById("scene").replaceChildren(
    ...scenes.map((s) => el("option", { value: s.name, text: s.name })));
  const algorithms = document.getElementById("algorithm");
  algorithms.replaceChildren(
    ...serverInfo.algorithms.map((a) => el("option", { value: a.name, text: a.name })));
  algorithms.addEventListener("change", showParameters);
  showParameters();
  document.getElementById("submit").addEventListener("submit", submit);
  refreshJobs();
  setInterval(refreshJobs, 1000);
}

start().catch((e) => {
  document.getElementById("server").textContent = "cannot reach partitad: " + e.message;
});
