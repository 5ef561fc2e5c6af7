// A small line plot on a canvas: the estimated error of the combined image and of each
// partition over the render's time, log scale (errors fall as 1/sqrt(t)).
"use strict";

const PLOT_COLORS = ["#1d1f21", "#3b7dd8", "#d8573b", "#3bb273", "#a23bd8", "#d8a53b",
                     "#3bc4d8", "#d83b8f", "#7a8a3b", "#6b6b6b"];

// series: Map name -> [[seconds, value], ...]
function drawPlot(canvas, series) {
  const g = canvas.getContext("2d");
  const W = canvas.width, H = canvas.height, left = 56, right = 120, top = 10, bottom = 30;
  g.clearRect(0, 0, W, H);
  const points = [...series.values()].flat().filter(([, v]) => v > 0);
  if (points.length === 0) return 0;
  const tMax = Math.max(...points.map(([t]) => t), 1e-3);
  const logs = points.map(([, v]) => Math.log10(v));
  let lo = Math.floor(Math.min(...logs)), hi = Math.ceil(Math.max(...logs));
  if (hi === lo) hi = lo + 1;
  const x = (t) => left + (W - left - right) * (t / tMax);
  const y = (v) => top + (H - top - bottom) * (1 - (Math.log10(v) - lo) / (hi - lo));
  g.strokeStyle = "#ccc";
  g.fillStyle = "#555";
  g.font = "11px sans-serif";
  for (let e = lo; e <= hi; ++e) {
    g.beginPath(); g.moveTo(left, y(10 ** e)); g.lineTo(W - right, y(10 ** e)); g.stroke();
    g.fillText("1e" + e, 8, y(10 ** e) + 4);
  }
  g.fillText("0 s", left, H - 10);
  g.fillText(formatDuration(tMax), W - right - 30, H - 10);
  let index = 0;
  for (const [name, data] of series) {
    const color = PLOT_COLORS[index++ % PLOT_COLORS.length];
    g.strokeStyle = color;
    g.lineWidth = name === "combined" ? 2 : 1;
    g.beginPath();
    data.filter(([, v]) => v > 0).forEach(([t, v], i) => i ? g.lineTo(x(t), y(v)) : g.moveTo(x(t), y(v)));
    g.stroke();
    g.fillStyle = color;
    g.fillText(name.slice(0, 18), W - right + 8, top + 12 * index);
  }
  return points.length;
}
