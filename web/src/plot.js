// SPDX-License-Identifier: MIT
// Line plots on a 2D canvas: axes with round-number ticks, one line per series (broken where the
// samples skip), a legend, and shaded x ranges (lost episodes).

// About `count` round tick values covering [lo, hi].
function ticks(lo, hi, count) {
  const span = hi - lo || 1;
  const raw = span / count, power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * power).find((s) => s >= raw);
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) out.push(+v.toPrecision(12));
  return out;
}

function range(values) {
  let lo = Infinity, hi = -Infinity;
  for (const v of values) if (Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  return lo <= hi ? [lo, hi] : [0, 1];
}

export function drawPlot(canvas, series, bands = []) {
  const ratio = window.devicePixelRatio || 1;
  const cssWidth = canvas.clientWidth || canvas.width, cssHeight = canvas.clientHeight || canvas.height;
  canvas.width = cssWidth * ratio;
  canvas.height = cssHeight * ratio;
  const g = canvas.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  g.clearRect(0, 0, cssWidth, cssHeight);
  if (!series.length) return;
  const [x0, x1] = range(series.flatMap((s) => s.x));
  const [, y1] = range(series.flatMap((s) => s.y));
  const y0 = 0;  // Times, errors and counts: from zero.
  const left = 48, right = 10, top = 22, bottom = 26;
  const w = cssWidth - left - right, h = cssHeight - top - bottom;
  const px = (x) => left + (x1 > x0 ? (x - x0) / (x1 - x0) : 0.5) * w;
  const py = (y) => top + h - (y1 > y0 ? (y - y0) / (y1 - y0) : 0.5) * h;
  g.font = '11px sans-serif';
  g.fillStyle = 'rgba(255, 90, 90, 0.18)';
  for (const [a, b] of bands) g.fillRect(px(a), top, Math.max(px(b + 1) - px(a), 2), h);
  g.strokeStyle = '#3a3f47';
  g.fillStyle = '#aab2bd';
  g.lineWidth = 1;
  g.textAlign = 'right';
  for (const v of ticks(y0, y1, 4)) {
    g.beginPath(); g.moveTo(left, py(v)); g.lineTo(left + w, py(v)); g.stroke();
    g.fillText(String(v), left - 4, py(v) + 4);
  }
  g.textAlign = 'center';
  for (const v of ticks(x0, x1, 6)) g.fillText(String(v), px(v), top + h + 16);
  let legendX = left;
  for (const s of series) {
    g.strokeStyle = s.color;
    g.lineWidth = 1.2;
    // A line breaks where the samples skip (lost frames): a step of more than 3 median steps.
    const steps = s.x.slice(1).map((x, i) => x - s.x[i]).sort((a, b) => a - b);
    const gap = 3 * (steps.length ? steps[steps.length >> 1] : Infinity);
    g.beginPath();
    s.x.forEach((x, i) => (i && x - s.x[i - 1] <= gap ? g.lineTo(px(x), py(s.y[i])) : g.moveTo(px(x), py(s.y[i]))));
    if (s.x.length === 1) g.arc(px(s.x[0]), py(s.y[0]), 2, 0, 2 * Math.PI);
    g.stroke();
    g.fillStyle = s.color;
    g.textAlign = 'left';
    g.fillText(s.label, legendX, 14);
    legendX += g.measureText(s.label).width + 18;
  }
}
