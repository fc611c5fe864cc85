// limbfuse report: axis ticks, a shared time window over the time plots
// (inputs, buttons, wheel zoom, drag pan) and legend toggles. No network,
// no libraries. docs/REPORT.md.
(function () {
  'use strict';
  var NS = 'http://www.w3.org/2000/svg';
  var plots = Array.prototype.slice.call(document.querySelectorAll('svg.plot'));
  var timePlots = plots.filter(function (p) { return p.classList.contains('time'); });

  // Absolute integer points of every run of a path written by limbfuse's
  // svg.rs: "M x y l dx dy dx dy ..." ("h0" marks a single point).
  function parseRuns(d) {
    var runs = [], run = null, re = /([MlLh])|(-?\d+(?:\.\d+)?)/g, m, cmd = null, nums = [];
    function flush() {
      if (cmd === 'M') { run = [[nums[0], nums[1]]]; runs.push(run); nums = nums.slice(2); cmd = 'l'; }
      if (cmd === 'l') { for (var i = 0; i + 1 < nums.length; i += 2) { var q = run[run.length - 1]; run.push([q[0] + nums[i], q[1] + nums[i + 1]]); } }
      if (cmd === 'L') { for (var k = 0; k + 1 < nums.length; k += 2) run.push([nums[k], nums[k + 1]]); }
      nums = [];
    }
    while ((m = re.exec(d)) !== null) {
      if (m[1]) { flush(); cmd = m[1]; } else { nums.push(+m[2]); }
    }
    flush();
    return runs;
  }

  function niceStep(span, n) {
    var raw = span / n, p = Math.pow(10, Math.floor(Math.log10(raw))), f = raw / p;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * p;
  }
  // (audit 2026-12-05: a tick summed up from a negative start is -2.8e-17,
  // which printed "-0.0": zero is "0")
  function fmt(v, step) {
    var dec = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
    if (Math.abs(v) < step * 1e-6) v = 0;
    return v.toFixed(Math.min(dec, 6));
  }
  function el(name, attrs, text) {
    var e = document.createElementNS(NS, name);
    for (var k in attrs) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function drawAxes(svg) {
    var area = svg.querySelector('svg.area'), g = svg.querySelector('g.axes');
    var vb = area.viewBox.baseVal, xs = +svg.dataset.xScale, ys = +svg.dataset.yScale;
    var ax = +area.getAttribute('x'), ay = +area.getAttribute('y');
    var aw = +area.getAttribute('width'), ah = +area.getAttribute('height');
    while (g.firstChild) g.removeChild(g.firstChild);
    var x0 = vb.x / xs, x1 = (vb.x + vb.width) / xs;
    var y1 = -vb.y / ys, y0 = -(vb.y + vb.height) / ys;
    var sx = niceStep(x1 - x0, 8), sy = niceStep(y1 - y0, 5), v, px, k;
    for (k = Math.ceil(x0 / sx); (v = k * sx) <= x1 + 1e-9 * sx; k++) {
      px = ax + (v - x0) / (x1 - x0) * aw;
      g.appendChild(el('line', { 'class': 'tick', x1: px, x2: px, y1: ay, y2: ay + ah }));
      g.appendChild(el('text', { 'class': 'ticklabel', x: px, y: ay + ah + 13, 'text-anchor': 'middle' }, fmt(v, sx)));
    }
    for (k = Math.ceil(y0 / sy); (v = k * sy) <= y1 + 1e-9 * sy; k++) {
      px = ay + (y1 - v) / (y1 - y0) * ah;
      g.appendChild(el('line', { 'class': 'tick', x1: ax, x2: ax + aw, y1: px, y2: px }));
      g.appendChild(el('text', { 'class': 'ticklabel', x: ax - 4, y: px + 4, 'text-anchor': 'end' }, fmt(v, sy)));
    }
    g.appendChild(el('text', { 'class': 'axislabel', x: ax + aw, y: ay + ah + 28, 'text-anchor': 'end' }, svg.dataset.xLabel));
    var yl = ay + ah / 2;
    g.appendChild(el('text', { 'class': 'axislabel', x: 12, y: yl, 'text-anchor': 'middle', transform: 'rotate(-90 12 ' + yl + ')' }, svg.dataset.yLabel));
  }

  // Time window shared by the time plots, in seconds.
  var full = null, cache = new Map();
  timePlots.forEach(function (svg) {
    var f = svg.querySelector('svg.area').getAttribute('data-full').split(' ').map(Number);
    var xs = +svg.dataset.xScale, a = f[0] / xs, b = (f[0] + f[2]) / xs;
    full = full ? [Math.min(full[0], a), Math.max(full[1], b)] : [a, b];
  });
  function runsOf(path) {
    if (!cache.has(path)) cache.set(path, parseRuns(path.getAttribute('d')));
    return cache.get(path);
  }
  function setWindow(a, b) {
    if (!full) return;
    var span = Math.max(b - a, 1e-3);
    span = Math.min(span, Math.max(full[1] - full[0], 1e-3));
    a = Math.max(full[0], Math.min(a, full[1] - span));
    b = a + span;
    timePlots.forEach(function (svg) {
      var area = svg.querySelector('svg.area'), xs = +svg.dataset.xScale;
      var lo = Infinity, hi = -Infinity, xa = a * xs, xb = b * xs;
      // A clipped start transient (y_range.rs) stays out of the y range
      // while it is under a quarter of the window: the estimates' points up
      // to data-clip-until are not fitted (the reference always is).
      var cu = svg.dataset.clipUntil === undefined ? -Infinity : +svg.dataset.clipUntil;
      var skip = cu > xa && xb - cu >= 3 * (cu - xa);
      area.querySelectorAll('path').forEach(function (p) {
        if (p.classList.contains('off')) return;
        var until = skip && p.dataset.series !== 'reference' ? cu : -Infinity;
        runsOf(p).forEach(function (run) {
          for (var i = 0; i < run.length; i++) {
            var q = run[i];
            if (q[0] >= xa && q[0] <= xb && q[0] > until) { if (q[1] < lo) lo = q[1]; if (q[1] > hi) hi = q[1]; }
          }
        });
      });
      if (!isFinite(lo)) { var f = area.getAttribute('data-full').split(' ').map(Number); lo = f[1]; hi = f[1] + f[3]; }
      var pad = Math.max((hi - lo) * 0.05, 1), y0 = lo - pad, y1 = hi + pad;
      // never narrower than the plot's minimum span (svg.rs min_y_span):
      // a constant keeps its +-0.5 unit window
      var minSpan = +svg.dataset.minYSpan || 0;
      if (y1 - y0 < minSpan) { var mid = (lo + hi) / 2; y0 = mid - minSpan / 2; y1 = mid + minSpan / 2; }
      area.setAttribute('viewBox', [xa, y0, xb - xa, y1 - y0].join(' '));
      drawAxes(svg);
    });
    var s = document.getElementById('win-start'), e = document.getElementById('win-end');
    if (s) s.value = a.toFixed(3);
    if (e) e.value = b.toFixed(3);
    document.body.dataset.window = a.toFixed(3) + ':' + b.toFixed(3);
  }
  function current() {
    var w = (document.body.dataset.window || '').split(':').map(Number);
    return w.length === 2 && isFinite(w[0]) ? w : full;
  }
  function on(id, f) { var b = document.getElementById(id); if (b) b.addEventListener('click', f); }
  // (an audit: start 10 and end 5, or an emptied field, gave a 1 ms window;
  // now an end before the start is swapped and an empty field keeps the
  // current window's end)
  on('win-apply', function () {
    var w = current(), a = parseFloat(document.getElementById('win-start').value),
      b = parseFloat(document.getElementById('win-end').value);
    if (!isFinite(a)) a = w[0];
    if (!isFinite(b)) b = w[1];
    if (b < a) { var t = a; a = b; b = t; }
    setWindow(a, b);
  });
  on('win-all', function () { setWindow(full[0], full[1]); });
  on('win-in', function () { var w = current(), c = (w[0] + w[1]) / 2, h = (w[1] - w[0]) / 4; setWindow(c - h, c + h); });
  on('win-out', function () { var w = current(), c = (w[0] + w[1]) / 2, h = (w[1] - w[0]); setWindow(c - h, c + h); });
  on('win-left', function () { var w = current(), d = (w[1] - w[0]) / 2; setWindow(w[0] - d, w[1] - d); });
  on('win-right', function () { var w = current(), d = (w[1] - w[0]) / 2; setWindow(w[0] + d, w[1] + d); });

  timePlots.forEach(function (svg) {
    var area = svg.querySelector('svg.area');
    function tAt(clientX) {
      var r = area.getBoundingClientRect(), w = current();
      return w[0] + (clientX - r.left) / r.width * (w[1] - w[0]);
    }
    svg.addEventListener('wheel', function (ev) {
      ev.preventDefault();
      var w = current(), t = tAt(ev.clientX), k = ev.deltaY > 0 ? 1.25 : 0.8;
      setWindow(t - (t - w[0]) * k, t + (w[1] - t) * k);
    }, { passive: false });
    var drag = null;
    svg.addEventListener('pointerdown', function (ev) { drag = { x: ev.clientX, w: current() }; svg.setPointerCapture(ev.pointerId); });
    svg.addEventListener('pointermove', function (ev) {
      if (!drag) return;
      var r = area.getBoundingClientRect(), dt = (ev.clientX - drag.x) / r.width * (drag.w[1] - drag.w[0]);
      setWindow(drag.w[0] - dt, drag.w[1] - dt);
    });
    svg.addEventListener('pointerup', function () { drag = null; });
  });

  document.querySelectorAll('.legend .key').forEach(function (key) {
    key.addEventListener('click', function () {
      var fig = key.closest('figure'), s = key.dataset.series, off = !key.classList.contains('off');
      key.classList.toggle('off', off);
      fig.querySelectorAll('svg.area path').forEach(function (p) { if (p.dataset.series === s) p.classList.toggle('off', off); });
    });
  });

  plots.forEach(drawAxes);
  if (full) setWindow(full[0], full[1]);
  document.body.dataset.ready = String(plots.length);
})();
