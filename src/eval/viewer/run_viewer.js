// hazmap view: the page script. The page (run_viewer.cpp) holds the run's data as JSON
// (#run-data) and every written frame's grids as one base64 zlib stream each
// (#grids-<i>, embedded_grids.hpp); this script unpacks a frame when it is shown, draws
// each map into its canvas with the view's pan and zoom, and keeps the readout, the
// plots and the URL (#frame=N) in step. Plain ES2017, no library: the page opens from
// disk with no network.
(function () {
  'use strict';

  // A failure anywhere below says so where the user looks, not only on the console.
  window.addEventListener('error', function (e) {
    var status = document.getElementById('status');
    status.textContent = 'page script failed: ' + e.message;
    status.className = 'error';
  });

  var data = JSON.parse(document.getElementById('run-data').textContent);
  var maps = data.maps, frames = data.frames;

  // SPEC 9's hazard palette (the run's PNGs use the same): unknown, traversable, hazard.
  var CLASS_RGB = [[90, 90, 90], [40, 170, 70], [220, 40, 40]];
  var CLASS_NAMES = ['unknown', 'traversable', 'hazard'];
  var CLASS_NODATA = 255;          // embedded_grids.hpp kClassNoData
  var NO_VALUE_RGB = CLASS_RGB[0];  // a cell without a height or variance looks unknown
  // How far one may zoom in and out, relative to a cell and to the fitted view: beyond
  // that the picture is one colour or a dot.
  var MAX_PIXELS_PER_CELL = 400, MAX_ZOOM_OUT = 8;
  var ROBOT_RING_PX = 7;           // the rover's ring, CSS pixels at any zoom
  var FIT_MARGIN = 1.02;           // a fitted grid leaves its border visible
  // A fitted view shows the map's known cells (what it found, not the empty window
  // around it): their bounding box grown on each side by this share of its larger side,
  // and by at least this many cells, so that the edge cells stay clear of the frame.
  var FIT_KNOWN_MARGIN = 0.05, FIT_KNOWN_MARGIN_CELLS = 2;
  var WHEEL_ZOOM_PER_PX = 0.0015;  // zoom factor exp(-k deltaY): a wheel notch (100) is 14 %
  var FRAME_CACHE = 48;            // unpacked frames kept (about 2 MB each at CADRE's sizes)
  // Categorical series colours (Tableau 10), as plot.cpp's charts.
  var SERIES = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2',
                '#7f7f7f', '#bcbd22', '#17becf'];

  var luts = {};
  Object.keys(data.colour_maps).forEach(function (k) {
    var hex = data.colour_maps[k], t = new Uint8Array(256 * 3);
    for (var i = 0; i < 256 * 3; i++) t[i] = parseInt(hex.substr(2 * i, 2), 16);
    luts[k] = t;
  });

  var state = {
    frame: frames.length - 1,
    shown: -1,          // the frame whose grids are drawn
    playing: false, timer: null,
    rangeMode: 'run',
    link: true,
    pinned: null,       // {x, y, width}: the views' pan and zoom, when not fitted
    hover: null,        // {x, y} in W
    quantity: {}        // map id -> hazard | height | sigma
  };
  maps.forEach(function (m) { state.quantity[m.id] = 'hazard'; });

  // ---------------------------------------------------------------- unpacking
  var cache = new Map();  // frame index -> Promise of the unpacked frame

  function base64Bytes(text) {
    var bin = atob(text.trim()), out = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }

  function inflate(bytes) {
    if (typeof DecompressionStream === 'undefined')
      return Promise.reject(new Error('this browser has no DecompressionStream (use a current ' +
                                      'Chrome, Edge, Firefox or Safari)'));
    var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Response(stream).arrayBuffer();
  }

  // Typed arrays read the platform's byte order; the page's is little-endian, as every
  // browser's is.
  function unpack(index) {
    if (cache.has(index)) {
      var p = cache.get(index);
      cache.delete(index);  // re-insert: most recently used last
      cache.set(index, p);
      return p;
    }
    var text = document.getElementById('grids-' + index).textContent;
    var promise = inflate(base64Bytes(text)).then(function (buffer) {
      var f = frames[index];
      return {
        images: {},
        boxes: {},  // knownBox's answers
        maps: f.maps.map(function (g) {
          var arrays = {};
          Object.keys(g.arrays).forEach(function (q) {
            var a = g.arrays[q];
            arrays[q] = a[0] === 'f32' ? new Float32Array(buffer, a[1], a[2])
                                       : new Uint8Array(buffer, a[1], a[2]);
          });
          var ext = [g.cols * g.resolution_m, g.rows * g.resolution_m];
          return {
            rows: g.rows, cols: g.cols, res: g.resolution_m,
            x0: g.center_m[0] - ext[0] / 2, y1: g.center_m[1] + ext[1] / 2,
            cx: g.center_m[0], cy: g.center_m[1], arrays: arrays, range: g.range
          };
        })
      };
    });
    cache.set(index, promise);
    while (cache.size > FRAME_CACHE) cache.delete(cache.keys().next().value);
    return promise;
  }

  // ---------------------------------------------------------------- colours
  function rangeFor(frameIndex, m, q) {
    var r = state.rangeMode === 'frame' ? frames[frameIndex].maps[m].range[q] : maps[m].range_run[q];
    if (!r) return [0, 1];
    if (!(r[1] > r[0])) return [r[0] - 0.001, r[0] + 0.001];
    return r;
  }

  function valueOf(g, q, i) {
    if (q === 'height') return g.arrays.height[i];
    var v = g.arrays.variance[i];
    return v >= 0 ? Math.sqrt(v) : NaN;
  }

  // The grid at one pixel per cell (row 0 = largest y, as an image), drawn scaled later.
  function gridImage(u, frameIndex, m, q) {
    var key = m + '/' + q + '/' + state.rangeMode;
    if (u.images[key]) return u.images[key];
    var g = u.maps[m], canvas = document.createElement('canvas');
    canvas.width = Math.max(1, g.cols);
    canvas.height = Math.max(1, g.rows);
    var ctx = canvas.getContext('2d'), img = ctx.createImageData(canvas.width, canvas.height);
    var px = img.data, n = g.rows * g.cols, i, k, rgb;
    if (q === 'hazard') {
      var cls = g.arrays.hazard;
      for (i = 0; i < n; i++) {
        rgb = CLASS_RGB[cls[i]] || CLASS_RGB[0];
        k = 4 * i;
        px[k] = rgb[0]; px[k + 1] = rgb[1]; px[k + 2] = rgb[2]; px[k + 3] = 255;
      }
    } else {
      var r = rangeFor(frameIndex, m, q), lut = luts[q], scale = 255 / (r[1] - r[0]);
      for (i = 0; i < n; i++) {
        var v = valueOf(g, q, i);
        k = 4 * i;
        if (isNaN(v)) {
          px[k] = NO_VALUE_RGB[0]; px[k + 1] = NO_VALUE_RGB[1]; px[k + 2] = NO_VALUE_RGB[2];
        } else {
          var level = Math.max(0, Math.min(255, Math.round((v - r[0]) * scale))) * 3;
          px[k] = lut[level]; px[k + 1] = lut[level + 1]; px[k + 2] = lut[level + 2];
        }
        px[k + 3] = 255;
      }
    }
    ctx.putImageData(img, 0, 0);
    u.images[key] = canvas;
    return canvas;
  }

  // ---------------------------------------------------------------- views
  // A view maps W to the canvas: centre (cx, cy) in W, mpp metres per CSS pixel. A fitted
  // view follows the known cells of what it shows, frame by frame (fitView); pan or zoom
  // pins it in W, "fit maps" or a double-click fits it again.
  var panels = maps.map(function (m, index) {
    var section = document.getElementById('map-' + m.id);
    return {
      index: index, map: m, section: section,
      canvas: section.querySelector('canvas.view'),
      legend: section.querySelector('.legend'),
      stats: section.querySelector('.stats'),
      view: { cx: 0, cy: 0, mpp: 0.01, fit: true }
    };
  });
  var unpacked = null;  // the shown frame's grids

  function canvasSize(p) {
    return [p.canvas.clientWidth || 360, p.canvas.clientHeight || 360];
  }

  // The bounding box in W [x0, y0, x1, y1] of the cells of map `m` that hold a value in
  // quantity `q` (a hazard class other than unknown; a height; a variance), or null.
  function knownBox(u, m, q) {
    var key = m + '/' + q;
    if (key in u.boxes) return u.boxes[key];
    var g = u.maps[m], r0 = g.rows, r1 = -1, c0 = g.cols, c1 = -1, row, col, i = 0;
    var a = q === 'hazard' ? g.arrays.hazard : q === 'height' ? g.arrays.height : g.arrays.variance;
    for (row = 0; row < g.rows; row++)
      for (col = 0; col < g.cols; col++, i++) {
        var v = a[i];
        if (q === 'hazard' ? v === 1 || v === 2 : !isNaN(v)) {
          if (row < r0) r0 = row;
          if (row > r1) r1 = row;
          if (col < c0) c0 = col;
          if (col > c1) c1 = col;
        }
      }
    // Row 0 is the largest y: rows r0..r1 span y1 - (r1 + 1) res .. y1 - r0 res.
    u.boxes[key] = r1 < 0 ? null : [g.x0 + c0 * g.res, g.y1 - (r1 + 1) * g.res,
                                    g.x0 + (c1 + 1) * g.res, g.y1 - r0 * g.res];
    return u.boxes[key];
  }

  // Fitted: the known cells of what the panel shows, with a margin; the whole grid when
  // none is known.
  function fitView(p) {
    if (!unpacked) return;
    var g = unpacked.maps[p.index], s = canvasSize(p);
    var box = knownBox(unpacked, p.index, quantityOf(p));
    if (!box) {
      p.view.cx = g.cx;
      p.view.cy = g.cy;
      p.view.mpp = Math.max(g.cols * g.res / s[0], g.rows * g.res / s[1], 1e-6) * FIT_MARGIN;
      return 'grid';
    }
    var pad = Math.max(FIT_KNOWN_MARGIN * Math.max(box[2] - box[0], box[3] - box[1]),
                       FIT_KNOWN_MARGIN_CELLS * g.res);
    p.view.cx = (box[0] + box[2]) / 2;
    p.view.cy = (box[1] + box[3]) / 2;
    p.view.mpp = Math.max((box[2] - box[0] + 2 * pad) / s[0], (box[3] - box[1] + 2 * pad) / s[1],
                          g.res / MAX_PIXELS_PER_CELL);
    return 'known';
  }

  function toScreen(p, x, y) {
    var s = canvasSize(p), v = p.view;
    return [(x - v.cx) / v.mpp + s[0] / 2, s[1] / 2 - (y - v.cy) / v.mpp];
  }

  function toWorld(p, sx, sy) {
    var s = canvasSize(p), v = p.view;
    return { x: v.cx + (sx - s[0] / 2) * v.mpp, y: v.cy - (sy - s[1] / 2) * v.mpp };
  }

  function clampZoom(p) {
    if (!unpacked) return;
    var g = unpacked.maps[p.index], s = canvasSize(p);
    var fit = Math.max(g.cols * g.res / s[0], g.rows * g.res / s[1], 1e-6);
    p.view.mpp = Math.min(Math.max(p.view.mpp, g.res / MAX_PIXELS_PER_CELL), fit * MAX_ZOOM_OUT);
  }

  // After a pan or zoom of `p`: pinned, and copied to the others when views are linked.
  function viewChanged(p) {
    p.view.fit = false;
    if (state.link)
      panels.forEach(function (o) {
        if (o !== p) o.view = { cx: p.view.cx, cy: p.view.cy, mpp: p.view.mpp, fit: false };
      });
    // Only linked views fit in one address; unlinked ones are not kept there.
    state.pinned = state.link ? { x: p.view.cx, y: p.view.cy, width: p.view.mpp * canvasSize(p)[0] }
                              : null;
    writeHash();
    requestDraw();
  }

  function fitAll(which) {
    which.forEach(function (o) { o.view.fit = true; });
    if (which.length === panels.length) state.pinned = null;
    writeHash();
    requestDraw();
  }

  // Every panel shows `width` metres across, centred on (x, y) in W.
  function pinAll(x, y, width) {
    panels.forEach(function (p) {
      p.view = { cx: x, cy: y, mpp: width / canvasSize(p)[0], fit: false };
    });
    state.pinned = { x: x, y: y, width: width };
  }

  function niceLength(metres) {
    var e = Math.pow(10, Math.floor(Math.log10(metres))), best = e;
    [1, 2, 5, 10].forEach(function (k) { if (k * e <= metres) best = k * e; });
    return best;
  }

  function lengthText(m) {
    if (m >= 1) return +m.toPrecision(3) + ' m';
    if (m >= 0.01) return +(m * 100).toPrecision(3) + ' cm';
    return +(m * 1000).toPrecision(3) + ' mm';
  }

  // The largest 1, 2 or 5 x 10^k metres within a quarter of the view, as the PNGs' bars
  // (map_render.hpp scale_bar_length_m).
  function drawScaleBar(ctx, p) {
    var s = canvasSize(p), len = niceLength(s[0] / 4 * p.view.mpp);
    var w = len / p.view.mpp, x = 10, y = s[1] - 14, label = lengthText(len);
    ctx.font = '12px system-ui, sans-serif';
    var tw = ctx.measureText(label).width;
    ctx.fillStyle = 'rgba(255,255,255,0.85)';
    ctx.fillRect(x - 5, y - 20, Math.max(w, tw) + 10, 28);
    ctx.fillStyle = '#000';
    ctx.fillRect(x, y, w, 4);
    ctx.fillRect(x, y - 4, 2, 8);
    ctx.fillRect(x + w - 2, y - 4, 2, 8);
    ctx.fillText(label, x, y - 7);
    // W's axes, north up.
    var ox = s[0] - 44, oy = s[1] - 12, L = 22;
    ctx.fillStyle = 'rgba(255,255,255,0.85)';
    ctx.fillRect(ox - 8, oy - L - 8, L + 24, L + 16);
    ctx.strokeStyle = '#000';
    ctx.fillStyle = '#000';
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(ox, oy); ctx.lineTo(ox + L, oy);
    ctx.moveTo(ox, oy); ctx.lineTo(ox, oy - L);
    ctx.stroke();
    ctx.beginPath();
    ctx.moveTo(ox + L + 4, oy); ctx.lineTo(ox + L - 2, oy - 3); ctx.lineTo(ox + L - 2, oy + 3);
    ctx.moveTo(ox, oy - L - 4); ctx.lineTo(ox - 3, oy - L + 2); ctx.lineTo(ox + 3, oy - L + 2);
    ctx.fill();
    ctx.fillText('x', ox + L + 6, oy + 4);
    ctx.fillText('y', ox + 5, oy - L + 4);
  }

  function processedIndex(name) { return data.processed.names.indexOf(name); }

  function drawPath(ctx, p) {
    var xs = data.poses.x_m, ys = data.poses.y_m;
    if (!xs.length) return;
    var now = processedIndex(frames[state.shown].name);
    function line(from, to, style, width, dash) {
      if (to - from < 1) return;
      ctx.beginPath();
      for (var i = from; i <= to; i++) {
        var q = toScreen(p, xs[i], ys[i]);
        if (i === from) ctx.moveTo(q[0], q[1]); else ctx.lineTo(q[0], q[1]);
      }
      ctx.setLineDash(dash);
      ctx.strokeStyle = style;
      ctx.lineWidth = width;
      ctx.stroke();
      ctx.setLineDash([]);
    }
    var last = xs.length - 1, upto = now < 0 ? last : now;
    line(0, upto, 'rgba(0,0,0,0.7)', 4, []);
    line(0, upto, '#fff', 2, []);
    line(upto, last, 'rgba(255,255,255,0.8)', 1.5, [4, 4]);
    if (now < 0) return;
    // The rover as the PNGs draw it: a hollow ring, so that the cells under it stay
    // visible, with a tick along its x axis (screen y points down: the angle flips).
    var c = toScreen(p, xs[now], ys[now]), yaw = data.poses.yaw_rad[now];
    var dir = [Math.cos(yaw), -Math.sin(yaw)], r = ROBOT_RING_PX;
    [['rgba(0,0,0,0.8)', 4], ['#fff', 2]].forEach(function (pen) {
      ctx.strokeStyle = pen[0];
      ctx.lineWidth = pen[1];
      ctx.beginPath();
      ctx.arc(c[0], c[1], r, 0, 2 * Math.PI);
      ctx.moveTo(c[0] + dir[0] * r, c[1] + dir[1] * r);
      ctx.lineTo(c[0] + dir[0] * 2 * r, c[1] + dir[1] * 2 * r);
      ctx.stroke();
    });
  }

  function drawHover(ctx, p) {
    if (!state.hover) return;
    var c = toScreen(p, state.hover.x, state.hover.y);
    ctx.strokeStyle = '#000';
    ctx.lineWidth = 3;
    ctx.beginPath(); ctx.arc(c[0], c[1], 6, 0, 2 * Math.PI); ctx.stroke();
    ctx.strokeStyle = '#ff0';
    ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(c[0], c[1], 6, 0, 2 * Math.PI); ctx.stroke();
  }

  function drawPanel(p) {
    var s = canvasSize(p), dpr = window.devicePixelRatio || 1;
    var w = Math.round(s[0] * dpr), h = Math.round(s[1] * dpr);
    if (p.canvas.width !== w || p.canvas.height !== h) { p.canvas.width = w; p.canvas.height = h; }
    var ctx = p.canvas.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = '#e9e9e9';
    ctx.fillRect(0, 0, s[0], s[1]);
    if (!unpacked) return;
    var g = unpacked.maps[p.index];
    var fitted = p.view.fit ? fitView(p) : 'no';
    var q = quantityOf(p);
    var img = gridImage(unpacked, state.shown, p.index, q);
    var tl = toScreen(p, g.x0, g.y1);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(img, tl[0], tl[1], g.cols * g.res / p.view.mpp, g.rows * g.res / p.view.mpp);
    ctx.strokeStyle = 'rgba(0,0,0,0.5)';
    ctx.lineWidth = 1;
    ctx.strokeRect(tl[0], tl[1], g.cols * g.res / p.view.mpp, g.rows * g.res / p.view.mpp);
    drawPath(ctx, p);
    drawHover(ctx, p);
    drawScaleBar(ctx, p);
    // For tests and tools reading the DOM: the scale and the part of W in view.
    p.section.dataset.metresPerPixel = p.view.mpp;
    var lo = toWorld(p, 0, s[1]), hi = toWorld(p, s[0], 0);
    p.section.dataset.viewBox = [lo.x, lo.y, hi.x, hi.y].join(',');
    p.section.dataset.fitted = fitted;  // known | grid (nothing known) | no (panned, zoomed)
  }

  function quantityOf(p) {
    var q = state.quantity[p.map.id];
    return p.map.quantities.indexOf(q === 'sigma' ? 'variance' : q) >= 0 ? q : 'hazard';
  }

  var drawPending = false;
  function requestDraw() {
    if (drawPending) return;
    drawPending = true;
    requestAnimationFrame(function () {
      drawPending = false;
      panels.forEach(drawPanel);
    });
  }

  // ---------------------------------------------------------------- legends, stats
  function fixed(v, digits) { return (v >= 0 ? '+' : '') + v.toFixed(digits); }

  // output.png_height_clip_pct cut from each end, as the run's height PNGs.
  function percentileText() {
    var c = data.clip_pct;
    return c > 0 ? +c.toPrecision(3) + '&ndash;' + +(100 - c).toPrecision(3) + ' %' : 'min&ndash;max';
  }

  function updateLegend(p) {
    var q = quantityOf(p), html = '';
    if (q === 'hazard') {
      html = CLASS_NAMES.map(function (name, c) {
        return '<span><span class="swatch" style="background:rgb(' + CLASS_RGB[c].join(',') +
               ')"></span>' + name + '</span>';
      }).join(' ');
      if (p.map.kind === 'footprint') html += ' <span>(where the rover\'s centre may go)</span>';
    } else {
      var r = rangeFor(state.shown, p.index, q), lut = luts[q], stops = [];
      for (var i = 0; i <= 8; i++) {
        var k = Math.round(i * 255 / 8) * 3;
        stops.push('rgb(' + lut[k] + ',' + lut[k + 1] + ',' + lut[k + 2] + ') ' + (i * 12.5) + '%');
      }
      var lo = q === 'height' ? fixed(r[0], 3) + ' m' : (r[0] * 1000).toFixed(1) + ' mm';
      var hi = q === 'height' ? fixed(r[1], 3) + ' m' : (r[1] * 1000).toFixed(1) + ' mm';
      html = '<span>' + (q === 'height' ? 'height' : '&sigma;') + '</span><span>' + lo +
             '</span><span class="ramp" style="background:linear-gradient(to right,' +
             stops.join(',') + ')"></span><span>' + hi + '</span><span>(' +
             (state.rangeMode === 'run' ? 'whole run' : 'this frame') + ', ' +
             percentileText() + ')</span>';
    }
    p.legend.innerHTML = html;
    p.section.querySelectorAll('.qsel button').forEach(function (b) {
      b.classList.toggle('active', b.dataset.q === q);
    });
  }

  function updateStats(p) {
    var g = unpacked.maps[p.index], cls = g.arrays.hazard, n = cls.length, known = 0, hazard = 0;
    for (var i = 0; i < n; i++) {
      if (cls[i] === 1 || cls[i] === 2) known++;
      if (cls[i] === 2) hazard++;
    }
    var cell = g.res * g.res;
    p.stats.dataset.known = known;
    p.stats.dataset.hazard = hazard;
    p.stats.textContent = 'known ' + (n ? (100 * known / n).toFixed(1) : '0') + ' % of ' + g.rows +
        ' x ' + g.cols + ' cells (' + (known * cell).toFixed(3) + ' m²), hazard ' +
        (hazard * cell).toFixed(4) + ' m²';
  }

  // ---------------------------------------------------------------- readout
  function cellAt(g, x, y) {
    var col = Math.floor((x - g.x0) / g.res), row = Math.floor((g.y1 - y) / g.res);
    if (col < 0 || row < 0 || col >= g.cols || row >= g.rows) return null;
    return { row: row, col: col, i: row * g.cols + col };
  }

  function td(cls, text, value) {
    return '<td class="' + cls + '"' + (value === undefined ? '' : ' data-value="' + value + '"') +
           '>' + text + '</td>';
  }

  function updateReadout() {
    var el = document.getElementById('readout');
    if (!state.hover || !unpacked) return;
    var x = state.hover.x, y = state.hover.y;
    var rows = panels.map(function (p) {
      var g = unpacked.maps[p.index], c = cellAt(g, x, y);
      if (!c) return '<tr data-map="' + p.map.id + '"><td>' + p.map.id + '</td>' +
                     '<td class="class" colspan="4">outside</td></tr>';
      var k = g.arrays.hazard[c.i], a = g.arrays, cells = '';
      cells += td('class', k === CLASS_NODATA ? 'no data' : CLASS_NAMES[k] || String(k), k);
      if (a.height) {
        var h = a.height[c.i], v = a.variance ? a.variance[c.i] : NaN, note = '';
        cells += td('height', isNaN(h) ? '&ndash;' : fixed(h, 4), h);
        cells += td('sigma', isNaN(v) ? '&ndash;' : (Math.sqrt(v) * 1000).toFixed(1), v);
        if (a.slope_x && !isNaN(h) && !isNaN(a.slope_x[c.i]) && !isNaN(a.slope_y[c.i])) {
          // CCM: the cell's plane h + sx dx + sy dy at the point (SPEC 6).
          var dx = x - (g.x0 + (c.col + 0.5) * g.res), dy = y - (g.y1 - (c.row + 0.5) * g.res);
          note = 'plane ' + fixed(h + a.slope_x[c.i] * dx + a.slope_y[c.i] * dy, 4);
        }
        cells += td('note', note);
      } else if (a.clearance) {
        var cl = a.clearance[c.i];
        cells += td('height', '') + td('sigma', '') +
                 td('note', isNaN(cl) ? '' : 'clear of ' + (cl * 100).toFixed(1) + ' cm', cl);
      } else {
        cells += td('height', '') + td('sigma', '') + td('note', '');
      }
      return '<tr data-map="' + p.map.id + '" title="cell row ' + c.row + ', column ' + c.col +
             '"><td>' + p.map.id + '</td>' + cells + '</tr>';
    });
    el.innerHTML = '<div id="readout-position" data-x="' + x + '" data-y="' + y + '">x ' +
        fixed(x, 3) + ' m, y ' + fixed(y, 3) + ' m in W, frame ' + frames[state.shown].name +
        '</div><table><thead><tr><th>map</th><th>class</th><th>height [m]</th><th>&sigma; [mm]</th>' +
        '<th>at the point</th></tr></thead><tbody>' + rows.join('') + '</tbody></table>';
  }

  // ---------------------------------------------------------------- plots
  var plots = [];

  function niceTicks(lo, hi, count) {
    if (!(hi > lo)) { hi = lo + 1; }
    var step = niceLength((hi - lo) / count);
    if ((hi - lo) / step > count * 1.5) step *= 2;
    var ticks = [];
    for (var t = Math.ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) ticks.push(+t.toPrecision(12));
    return ticks;
  }

  // A line chart over frames: series [{name, values}], x = index into `names`.
  function addPlot(container, title, unit, names, series) {
    var canvas = document.createElement('canvas');
    canvas.className = 'plot';
    canvas.id = 'plot-' + (plots.length + 1);
    canvas.setAttribute('aria-label', title);
    container.appendChild(canvas);
    var plot = { canvas: canvas, title: title, unit: unit, names: names, series: series, box: null };
    canvas.addEventListener('click', function (e) {
      if (!plot.box) return;
      var r = canvas.getBoundingClientRect(), b = plot.box;
      var i = Math.round((e.clientX - r.left - b.left) / b.width * Math.max(1, names.length - 1));
      goToName(names[Math.max(0, Math.min(names.length - 1, i))]);
    });
    plots.push(plot);
  }

  function drawPlot(plot) {
    var c = plot.canvas, dpr = window.devicePixelRatio || 1;
    var W = c.clientWidth || 480, H = c.clientHeight || 230;
    c.width = Math.round(W * dpr);
    c.height = Math.round(H * dpr);
    var ctx = c.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, W, H);
    var lo = Infinity, hi = -Infinity, n = plot.names.length;
    plot.series.forEach(function (s) {
      s.values.forEach(function (v) {
        if (v !== null && isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
      });
    });
    if (lo > hi) { lo = 0; hi = 1; }
    lo = Math.min(lo, 0);
    var ticks = niceTicks(lo, hi, 5);
    hi = Math.max(hi, ticks[ticks.length - 1]);
    // The legend's rows first: they decide the plot's height.
    ctx.font = '12px system-ui, sans-serif';
    var legend = [], lx = 58, ly = 0;
    plot.series.forEach(function (s) {
      var w = ctx.measureText(s.name).width + 30;
      if (lx + w > W - 28 && lx > 58) { lx = 58; ly++; }
      legend.push({ x: lx, row: ly });
      lx += w;
    });
    var legendRows = plot.series.length ? ly + 1 : 0;
    var box = { left: 58, top: 26, width: W - 58 - 28, height: H - 26 - 38 - 15 * Math.max(0, legendRows - 1) };
    plot.box = box;
    function X(i) { return box.left + (n > 1 ? i / (n - 1) : 0.5) * box.width; }
    function Y(v) { return box.top + box.height * (1 - (v - lo) / (hi - lo || 1)); }
    ctx.font = '12px system-ui, sans-serif';
    ctx.fillStyle = '#222';
    ctx.fillText(plot.title + (plot.unit ? ' [' + plot.unit + ']' : ''), box.left, 15);
    ctx.strokeStyle = '#ddd';
    ctx.lineWidth = 1;
    ctx.textAlign = 'right';
    ticks.forEach(function (t) {
      ctx.beginPath(); ctx.moveTo(box.left, Y(t)); ctx.lineTo(box.left + box.width, Y(t)); ctx.stroke();
      ctx.fillText(String(+t.toPrecision(6)), box.left - 5, Y(t) + 4);
    });
    ctx.textAlign = 'center';
    var every = Math.max(1, Math.ceil(n / Math.max(1, Math.floor(box.width / 70))));
    for (var i = 0; i < n; i += every) ctx.fillText(plot.names[i], X(i), box.top + box.height + 16);
    ctx.textAlign = 'left';
    ctx.strokeStyle = '#888';
    ctx.strokeRect(box.left, box.top, box.width, box.height);
    // The shown frame.
    var at = frames[state.shown] ? plot.names.indexOf(frames[state.shown].name) : -1;
    if (at >= 0) {
      ctx.strokeStyle = '#000';
      ctx.setLineDash([3, 3]);
      ctx.beginPath(); ctx.moveTo(X(at), box.top); ctx.lineTo(X(at), box.top + box.height); ctx.stroke();
      ctx.setLineDash([]);
    }
    plot.series.forEach(function (s, k) {
      var colour = SERIES[k % SERIES.length];
      ctx.strokeStyle = colour;
      ctx.fillStyle = colour;
      ctx.lineWidth = 1.8;
      ctx.beginPath();
      // Missing values (areas of frames not written, every_n > 1) are bridged.
      var open = false;
      s.values.forEach(function (v, i) {
        if (v === null || !isFinite(v)) return;
        if (open) ctx.lineTo(X(i), Y(v)); else ctx.moveTo(X(i), Y(v));
        open = true;
      });
      ctx.stroke();
      if (n < 60) s.values.forEach(function (v, i) {
        if (v !== null && isFinite(v)) ctx.fillRect(X(i) - 1.5, Y(v) - 1.5, 3, 3);
      });
      var at = legend[k], y = box.top + box.height + 32 + 15 * at.row;
      ctx.fillRect(at.x, y - 4, 12, 3);
      ctx.fillStyle = '#222';
      ctx.fillText(s.name, at.x + 15, y);
    });
  }

  function buildPlots() {
    var pf = data.processed, box = document.getElementById('plots');
    var names = pf.names;
    addPlot(box, 'points per frame', '', names, [
      { name: 'points', values: pf.points },
      { name: 'below ground', values: pf.points_below_ground },
      { name: 'unsupported disparities', values: pf.disparities_unsupported }]);
    addPlot(box, 'time per stage', 'ms', names, Object.keys(pf.ms).map(function (k) {
      return { name: k, values: pf.ms[k] };
    }));
    function areaSeries(f) {
      return maps.map(function (m) {
        var a = pf.areas_m2[m.id];
        return { name: m.id, values: a.hazard.map(function (h, i) { return f(a, i); }) };
      });
    }
    addPlot(box, 'known area (traversable + hazard)', 'm²', names, areaSeries(function (a, i) {
      return a.hazard[i] === null || a.traversable[i] === null ? null : a.hazard[i] + a.traversable[i];
    }));
    addPlot(box, 'hazard area', 'm²', names, areaSeries(function (a, i) { return a.hazard[i]; }));
    if (!data.eval) return;
    var ev = data.eval, eb = document.getElementById('eval-plots');
    [['height_rms_m', 'height RMS', 'cm', 100, true],
     ['hazard_recall', 'hazard recall (obstacles labelled hazard)', '%', 100, false],
     ['missed_m2', 'missed obstacle area', 'cm²', 1e4, false],
     ['false_alarm_fraction', 'false alarm area / known area', '%', 100, false],
     ['unknown_fraction', 'unknown fraction of the window', '%', 100, false]].forEach(function (d) {
      var per = ev.per_frame[d[0]];
      if (!per) return;
      var layers = ev.layers.filter(function (l) { return !(d[4] && /^(fused|footprint)$/.test(l)); });
      addPlot(eb, d[1], d[2], ev.frames, layers.map(function (l) {
        return { name: l, values: per[l].map(function (v) { return v === null ? null : v * d[3]; }) };
      }));
    });
  }

  function drawPlots() { plots.forEach(drawPlot); }

  // ---------------------------------------------------------------- frames
  var status = document.getElementById('status');
  var slider = document.getElementById('frame-slider');

  function setStatus(text, error) {
    status.textContent = text;
    status.classList.toggle('error', !!error);
  }

  function showFrame(i) {
    i = Math.max(0, Math.min(frames.length - 1, i | 0));
    state.frame = i;
    slider.value = i;
    document.getElementById('frame-label').textContent =
        'frame ' + frames[i].name + '  (' + (i + 1) + ' / ' + frames.length + ')';
    writeHash();
    return unpack(i).then(function (u) {
      if (state.frame !== i) return;  // a later request won
      unpacked = u;
      state.shown = i;
      document.body.dataset.shownFrame = frames[i].name;
      panels.forEach(function (p) { updateLegend(p); updateStats(p); });
      updateReadout();
      updateErrorMaps();
      requestDraw();
      drawPlots();
      setStatus('');
      if (i + 1 < frames.length) unpack(i + 1);  // ready for the next step or play tick
    }).catch(function (e) {
      setStatus('cannot show frame ' + frames[i].name + ': ' + e.message, true);
      stop();
    });
  }

  function goToName(name) {
    var i = frames.findIndex(function (f) { return f.name === name; });
    if (i < 0) {
      // Not written: the nearest written frame in processing order.
      var at = processedIndex(name), best = 0, bestDistance = Infinity;
      frames.forEach(function (f, k) {
        var d = Math.abs(processedIndex(f.name) - at);
        if (d < bestDistance) { bestDistance = d; best = k; }
      });
      i = best;
    }
    showFrame(i);
  }

  function updateErrorMaps() {
    var box = document.getElementById('error-maps');
    if (!box) return;
    var figures = box.querySelectorAll('figure'), any = false;
    figures.forEach(function (f) {
      var here = f.dataset.frame === frames[state.shown].name;
      f.classList.toggle('current', here);
      any = any || here;
    });
    box.classList.toggle('all', !any);  // none for this frame: show what there is
  }

  var playButton = document.getElementById('play');
  function stop() {
    state.playing = false;
    clearTimeout(state.timer);
    playButton.innerHTML = '&#9654; play';
  }
  function tick() {
    if (!state.playing) return;
    if (state.frame >= frames.length - 1) { stop(); return; }
    var started = Date.now(), interval = 1000 / +document.getElementById('fps').value;
    showFrame(state.frame + 1).then(function () {
      if (state.playing) state.timer = setTimeout(tick, Math.max(0, interval - (Date.now() - started)));
    });
  }
  function togglePlay() {
    if (state.playing) { stop(); return; }
    state.playing = true;
    playButton.innerHTML = '&#10074;&#10074; pause';
    if (state.frame >= frames.length - 1) showFrame(0).then(function () { state.timer = setTimeout(tick, 0); });
    else tick();
  }

  // #frame=N (a frame's name, else its position from 0), &q=hazard|height|sigma (every
  // layer), &range=run|frame, &at=x,y (the readout's point in W), &view=x,y,width (every
  // map centred on x, y in W, width metres across): a link opens a view.
  function readHash() {
    var h = {};
    location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
      var at = kv.indexOf('=');
      if (at > 0) h[decodeURIComponent(kv.slice(0, at))] = decodeURIComponent(kv.slice(at + 1));
    });
    return h;
  }
  // Browsers throttle (and complain about) frequent history updates: a drag or a wheel
  // spin updates the address once it has settled.
  var HASH_DELAY_MS = 250, hashTimer = null;
  function writeHash() {
    clearTimeout(hashTimer);
    hashTimer = setTimeout(writeHashNow, HASH_DELAY_MS);
  }
  function writeHashNow() {
    var h = readHash();
    h.frame = frames[state.frame].name;
    if (state.pinned)
      h.view = [state.pinned.x, state.pinned.y, state.pinned.width].map(function (v) {
        return +v.toPrecision(6);
      }).join(',');
    else delete h.view;
    var text = Object.keys(h).map(function (k) { return k + '=' + h[k]; }).join('&');
    if (location.hash !== '#' + text) history.replaceState(null, '', '#' + text);
  }
  function frameFromHash(h) {
    if (h.frame === undefined) return frames.length - 1;
    var byName = frames.findIndex(function (f) { return f.name === h.frame; });
    if (byName >= 0) return byName;
    var n = parseInt(h.frame, 10);
    return isNaN(n) ? frames.length - 1 : (n < 0 ? frames.length + n : n);
  }

  // ---------------------------------------------------------------- wiring
  panels.forEach(function (p) {
    var c = p.canvas, drag = null;
    c.addEventListener('wheel', function (e) {
      e.preventDefault();
      var r = c.getBoundingClientRect(), sx = e.clientX - r.left, sy = e.clientY - r.top;
      var w = toWorld(p, sx, sy), s = canvasSize(p);
      p.view.mpp *= Math.exp(e.deltaY * WHEEL_ZOOM_PER_PX);
      clampZoom(p);
      p.view.cx = w.x - (sx - s[0] / 2) * p.view.mpp;
      p.view.cy = w.y + (sy - s[1] / 2) * p.view.mpp;
      viewChanged(p);
    }, { passive: false });
    c.addEventListener('pointerdown', function (e) {
      drag = { x: e.clientX, y: e.clientY };
      try {
        c.setPointerCapture(e.pointerId);  // keeps the drag when the pointer leaves the map
      } catch (err) { /* a synthetic event's pointer cannot be captured */ }
    });
    c.addEventListener('pointermove', function (e) {
      var r = c.getBoundingClientRect();
      if (drag) {
        var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
        if (dx || dy) {
          p.view.cx -= dx * p.view.mpp;
          p.view.cy += dy * p.view.mpp;
          drag.x = e.clientX; drag.y = e.clientY;
          viewChanged(p);
        }
      }
      state.hover = toWorld(p, e.clientX - r.left, e.clientY - r.top);
      updateReadout();
      requestDraw();
    });
    c.addEventListener('pointerup', function () { drag = null; });
    c.addEventListener('pointercancel', function () { drag = null; });
    c.addEventListener('dblclick', function () { fitAll(state.link ? panels : [p]); });
    p.section.querySelectorAll('.qsel button').forEach(function (b) {
      b.addEventListener('click', function () {
        state.quantity[p.map.id] = b.dataset.q;
        updateLegend(p);
        requestDraw();
      });
    });
  });

  document.querySelectorAll('#controls button[data-all]').forEach(function (b) {
    b.addEventListener('click', function () { setAll(b.dataset.all); });
  });
  function setAll(q) {
    maps.forEach(function (m) { if (m.kind === 'layer') state.quantity[m.id] = q; });
    document.querySelectorAll('#controls button[data-all]').forEach(function (o) {
      o.classList.toggle('active', o.dataset.all === q);
    });
    if (unpacked) panels.forEach(updateLegend);
    requestDraw();
  }
  slider.addEventListener('input', function () { showFrame(+slider.value); });
  document.getElementById('prev').addEventListener('click', function () { showFrame(state.frame - 1); });
  document.getElementById('next').addEventListener('click', function () { showFrame(state.frame + 1); });
  playButton.addEventListener('click', togglePlay);
  document.getElementById('range-mode').addEventListener('change', function (e) {
    state.rangeMode = e.target.value;
    if (unpacked) panels.forEach(updateLegend);
    requestDraw();
  });
  document.getElementById('link').addEventListener('change', function (e) { state.link = e.target.checked; });
  document.getElementById('fit').addEventListener('click', function () { fitAll(panels); });
  document.addEventListener('keydown', function (e) {
    if (/^(INPUT|SELECT|TEXTAREA|BUTTON)$/.test(e.target.tagName)) return;
    if (e.key === 'ArrowLeft') showFrame(state.frame - 1);
    else if (e.key === 'ArrowRight') showFrame(state.frame + 1);
    else if (e.key === ' ') { e.preventDefault(); togglePlay(); }
  });
  // The readout stays in view below the sticky controls, whose height depends on the width.
  function placeSide() {
    document.getElementById('side').style.top =
        (document.getElementById('controls').offsetHeight + 8) + 'px';
  }
  window.addEventListener('resize', function () { placeSide(); requestDraw(); drawPlots(); });
  placeSide();
  window.addEventListener('hashchange', function () {
    var i = frameFromHash(readHash());
    if (i !== state.frame) showFrame(i);
  });

  var initial = readHash();
  if (initial.range === 'frame' || initial.range === 'run') {
    state.rangeMode = initial.range;
    document.getElementById('range-mode').value = initial.range;
  }
  setAll(/^(hazard|height|sigma)$/.test(initial.q) ? initial.q : 'hazard');
  if (initial.at) {
    var xy = initial.at.split(',').map(Number);
    if (xy.length === 2 && isFinite(xy[0]) && isFinite(xy[1])) state.hover = { x: xy[0], y: xy[1] };
  }
  if (initial.view) {
    var v = initial.view.split(',').map(Number);
    if (v.length === 3 && v.every(isFinite) && v[2] > 0) pinAll(v[0], v[1], v[2]);
  }
  buildPlots();
  showFrame(frameFromHash(initial));
})();
