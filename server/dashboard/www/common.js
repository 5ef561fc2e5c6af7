// Shared by the dashboard's pages: the API (proto3 JSON of partita.v1, see dashboard_server.h)
// and the formatting of numbers, times and states.
"use strict";

const api = {
  async get(path) {
    const response = await fetch(path, { cache: "no-store" });
    return api.answer(response);
  },
  // Requests that change something carry X-Partita: 1 (http_access.h).
  async send(method, path, body) {
    const init = { method, headers: { "X-Partita": "1" } };
    if (body !== undefined) {
      init.headers["Content-Type"] = "application/json";
      init.body = JSON.stringify(body);
    }
    return api.answer(await fetch(path, init));
  },
  // A file as the raw body (a scene to /api/uploads: streamed to the store as it arrives).
  async sendFile(path, file) {
    return api.answer(await fetch(path, { method: "POST", headers: { "X-Partita": "1" },
                                          body: file }));
  },
  async answer(response) {
    if (response.status === 204) return null;
    const text = await response.text();
    let data = null;
    try { data = text ? JSON.parse(text) : null; } catch (e) { data = { error: text }; }
    if (!response.ok) {
      const error = new Error((data && data.error) || response.statusText);
      error.code = data && data.code;
      throw error;
    }
    return data;
  },
};

const STATES = {
  JOB_STATE_QUEUED: "QUEUED", JOB_STATE_LOADING: "LOADING", JOB_STATE_PREPASS: "PREPASS",
  JOB_STATE_RENDERING: "RENDERING", JOB_STATE_DONE: "DONE", JOB_STATE_FAILED: "FAILED",
  JOB_STATE_CANCELLED: "CANCELLED",
};
const stateName = (s) => STATES[s] || "QUEUED";
const isTerminal = (s) => ["DONE", "FAILED", "CANCELLED"].includes(stateName(s));

function el(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (key === "class") node.className = value;
    else if (key === "text") node.textContent = value;
    else node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

function formatDuration(seconds) {
  if (!(seconds >= 0) || !isFinite(seconds)) return "";
  if (seconds < 60) return seconds.toFixed(seconds < 10 ? 1 : 0) + " s";
  const m = Math.floor(seconds / 60), s = Math.round(seconds % 60);
  if (m < 60) return `${m} min ${s} s`;
  return `${Math.floor(m / 60)} h ${m % 60} min`;
}

function formatNumber(x) {
  if (x === undefined || x === null || x === "") return "";
  const v = Number(x);
  if (!isFinite(v)) return String(x);
  if (v !== 0 && (Math.abs(v) >= 1e6 || Math.abs(v) < 1e-3)) return v.toExponential(3);
  return Number.isInteger(v) ? String(v) : v.toPrecision(4);
}

function formatRate(progress) {
  if (!progress || !progress.rate_per_second) return "";
  return formatNumber(progress.rate_per_second) + " " + (progress.unit || "") + "/s";
}

function formatTime(unixMs) {
  const ms = Number(unixMs || 0);
  return ms > 0 ? new Date(ms).toLocaleTimeString() : "";
}

// Done over total; for a time budget (no total) elapsed over elapsed + ETA.
function progressFraction(progress) {
  if (!progress) return 0;
  if (progress.total) return Math.max(0, Math.min(1, Number(progress.done || 0) / Number(progress.total)));
  const elapsed = Number(progress.elapsed_seconds || 0), eta = Number(progress.eta_seconds);
  return eta > 0 ? elapsed / (elapsed + eta) : 0;
}

// A ParameterValue (proto3 JSON) as text.
function parameterText(value) {
  if (!value) return "";
  if ("bool_value" in value) return String(value.bool_value);
  if ("int_value" in value) return String(value.int_value);
  if ("uint_value" in value) return String(value.uint_value);
  if ("real_value" in value) return formatNumber(value.real_value);
  if ("text_value" in value) return value.text_value;
  if ("rgb_value" in value) {
    const c = value.rgb_value;
    return [c.r || 0, c.g || 0, c.b || 0].map(formatNumber).join(", ");
  }
  return "";
}

function sceneText(spec) {
  const scene = (spec && spec.scene) || {};
  return scene.scene_name || spec.scene_file || "upload";
}
