// plots.js: a small plotter on Canvas 2D (lines, histogram bars and
// horizontal reference lines, with axes, ticks and a legend). page.js draws
// its speed, energy, drift and pressure plots with it.
'use strict';

const LEGEND_ROW = 15;  // CSS pixels a legend row takes

// Round tick positions (1, 2 or 5 times a power of ten), about `count` of them over [lo, hi].
function niceTicks(lo, hi, count) {
  const raw = (hi - lo) / count;
  const power = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((f) => f * power).find((s) => s >= raw * 0.999);
  const ticks = [];
  for (let i = Math.ceil(lo / step); i * step <= hi + step * 1e-9; i++) ticks.push(i * step);
  return { ticks, step };
}

// A tick label with as many decimals as the step needs; tiny or huge values in exponent form.
function formatTick(value, step) {
  if (Math.abs(value) < step * 1e-6) return '0';
  if (step < 1e-3 || step >= 1e4) return value.toExponential(1).replace('e+', 'e');
  return value.toFixed(Math.max(0, -Math.floor(Math.log10(step))));
}

class Plot {
  // options: xLabel, yLabel, includeZero (keep y = 0 in view), empty (text shown without data).
  constructor(canvas, options) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.options = Object.assign({ includeZero: false, empty: 'waiting for data…' }, options);
  }

  // series: [{ kind: 'line', xs, ys } | { kind: 'bars', edges, heights } | { kind: 'hline', y },
  //          each with label, color and optionally dash (a line-dash array)].
  draw(series) {
    const { canvas, ctx, options } = this;
    // Draw at the display's resolution, in CSS pixels.
    const ratio = window.devicePixelRatio || 1;
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.round(width * ratio) || canvas.height !== Math.round(height * ratio)) {
      canvas.width = Math.round(width * ratio);
      canvas.height = Math.round(height * ratio);
    }
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    ctx.clearRect(0, 0, width, height);
    ctx.font = '11px system-ui, sans-serif';

    const box = { left: 56, right: width - 10, top: 10, bottom: height - 34 };
    const legend = this.layoutLegend(series, width - 90);  // room for the widest y axis
    box.top += legend.rows * LEGEND_ROW;
    const range = this.ranges(series);
    if (!range) {
      this.frame(box);
      ctx.fillStyle = '#8a919c';
      ctx.textAlign = 'center';
      ctx.fillText(options.empty, (box.left + box.right) / 2, (box.top + box.bottom) / 2);
      return;
    }
    // The y axis as wide as its longest tick label.
    const yTicks = niceTicks(range.y0, range.y1, Math.max(2, (box.bottom - box.top) / 35));
    box.left = 28 + Math.max(...yTicks.ticks.map((y) => ctx.measureText(formatTick(y, yTicks.step)).width));
    const toX = (x) => box.left + ((x - range.x0) / (range.x1 - range.x0)) * (box.right - box.left);
    const toY = (y) => box.bottom - ((y - range.y0) / (range.y1 - range.y0)) * (box.bottom - box.top);
    this.axes(box, range, yTicks, toX, toY);

    ctx.save();
    ctx.beginPath();
    ctx.rect(box.left, box.top, box.right - box.left, box.bottom - box.top);
    ctx.clip();
    for (const s of series) {
      ctx.strokeStyle = ctx.fillStyle = s.color;
      ctx.setLineDash(s.dash || []);
      ctx.lineWidth = 1.5;
      if (s.kind === 'bars') {
        ctx.globalAlpha = 0.45;
        s.heights.forEach((h, i) => {
          const left = toX(s.edges[i]), right = toX(s.edges[i + 1]);
          ctx.fillRect(left, toY(h), Math.max(1, right - left - 1), toY(0) - toY(h));
        });
        ctx.globalAlpha = 1;
      } else if (s.kind === 'hline') {
        ctx.beginPath();
        ctx.moveTo(box.left, toY(s.y));
        ctx.lineTo(box.right, toY(s.y));
        ctx.stroke();
      } else {
        ctx.beginPath();
        s.xs.forEach((x, i) => (i ? ctx.lineTo(toX(x), toY(s.ys[i])) : ctx.moveTo(toX(x), toY(s.ys[i]))));
        ctx.stroke();
      }
    }
    ctx.restore();
    this.legend(legend, box);
  }

  // The data's extent, padded; null when there is nothing to draw.
  ranges(series) {
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    const takeX = (x) => { if (Number.isFinite(x)) { x0 = Math.min(x0, x); x1 = Math.max(x1, x); } };
    const takeY = (y) => { if (Number.isFinite(y)) { y0 = Math.min(y0, y); y1 = Math.max(y1, y); } };
    for (const s of series) {
      if (s.kind === 'bars') { s.edges.forEach(takeX); s.heights.forEach(takeY); takeY(0); }
      else if (s.kind === 'hline') takeY(s.y);
      else { s.xs.forEach(takeX); s.ys.forEach(takeY); }
    }
    if (!(x1 >= x0) || !(y1 >= y0)) return null;
    if (this.options.includeZero) { y0 = Math.min(y0, 0); y1 = Math.max(y1, 0); }
    if (x1 === x0) { x0 -= 0.5; x1 += 0.5; }
    // A flat series still gets a visible band around it; a zero baseline stays at the bottom.
    const pad = y1 > y0 ? 0.08 * (y1 - y0) : Math.abs(y0) * 0.1 || 1;
    return { x0, x1, y0: y0 === 0 ? 0 : y0 - pad, y1: y1 + pad };
  }

  frame(box) {
    const ctx = this.ctx;
    ctx.strokeStyle = '#aab1bb';
    ctx.lineWidth = 1;
    ctx.strokeRect(box.left + 0.5, box.top + 0.5, box.right - box.left, box.bottom - box.top);
  }

  axes(box, range, yt, toX, toY) {
    const ctx = this.ctx;
    const xt = niceTicks(range.x0, range.x1, Math.max(2, (box.right - box.left) / 70));
    ctx.lineWidth = 1;
    ctx.fillStyle = '#4a525e';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'top';
    for (const x of xt.ticks) {
      const px = Math.round(toX(x)) + 0.5;
      ctx.strokeStyle = '#eceef1';
      ctx.beginPath(); ctx.moveTo(px, box.top); ctx.lineTo(px, box.bottom); ctx.stroke();
      ctx.fillText(formatTick(x, xt.step), px, box.bottom + 4);
    }
    ctx.textAlign = 'right';
    ctx.textBaseline = 'middle';
    for (const y of yt.ticks) {
      const py = Math.round(toY(y)) + 0.5;
      ctx.strokeStyle = '#eceef1';
      ctx.beginPath(); ctx.moveTo(box.left, py); ctx.lineTo(box.right, py); ctx.stroke();
      ctx.fillText(formatTick(y, yt.step), box.left - 5, py);
    }
    this.frame(box);
    ctx.font = '12px system-ui, sans-serif';
    ctx.fillStyle = '#2b313a';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'bottom';
    ctx.fillText(this.options.xLabel, (box.left + box.right) / 2, box.bottom + 32);
    ctx.save();
    ctx.translate(12, (box.top + box.bottom) / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textBaseline = 'middle';
    ctx.fillText(this.options.yLabel, 0, 0);
    ctx.restore();
  }

  // The labelled series in rows above the plot, so the legend never hides data.
  layoutLegend(series, width) {
    const ctx = this.ctx, items = [];
    let x = 0, row = 0;
    for (const s of series.filter((e) => e.label)) {
      const w = 26 + ctx.measureText(s.label).width;
      if (x > 0 && x + w > width) [x, row] = [0, row + 1];
      items.push({ s, x, row });
      x += w + 14;
    }
    return { items, rows: items.length ? row + 1 : 0 };
  }

  legend({ items }, box) {
    const ctx = this.ctx;
    ctx.font = '11px system-ui, sans-serif';  // as measured in layoutLegend
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    for (const { s, x, row } of items) {
      const left = box.left + x, y = 8 + LEGEND_ROW * (row + 0.5);
      ctx.strokeStyle = ctx.fillStyle = s.color;
      if (s.kind === 'bars') {
        ctx.globalAlpha = 0.45;
        ctx.fillRect(left, y - 5, 18, 10);
        ctx.globalAlpha = 1;
      } else {
        ctx.setLineDash(s.dash || []);
        ctx.lineWidth = 2;
        ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(left + 18, y); ctx.stroke();
        ctx.setLineDash([]);
      }
      ctx.fillStyle = '#2b313a';
      ctx.fillText(s.label, left + 24, y);
    }
  }
}
