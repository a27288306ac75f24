// vpsim's per-layer sections and beam kernel, beside the 3D view. A classic script: the data
// comes from sections.js (window.VPSIM_SECTIONS, window.VPSIM_KERNEL), loaded before it, since
// Chromium blocks fetch() and ES modules on file://. The section follows the 3D view's layer
// slider (#view3d-clip: the clip at the top of layer k shows layer k's section); a page address
// ending in #layer=K moves the slider there once drawn (the browser test uses it). Each canvas
// gets data-rendered="1" when drawn; the section canvas also data-layer and data-draws.
(function () {
  'use strict';
  function decode(text, Type) {
    var bin = atob(text), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return Type === Uint8Array ? bytes : new Type(bytes.buffer);
  }
  // Tick values for [lo, hi]: steps of 1, 2 or 5 x 10^n, about `count` of them.
  function ticks(lo, hi, count) {
    var raw = (hi - lo) / count, p = Math.pow(10, Math.floor(Math.log10(raw)));
    var step = raw / p < 1.5 ? p : raw / p < 3.5 ? 2 * p : raw / p < 7.5 ? 5 * p : 10 * p;
    var out = [];
    for (var v = Math.ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) out.push(v);
    return out;
  }
  function label(v) { return String(Math.round(v * 1e6) / 1e6); }
  // Axes round the plot box (px) for x in [x0, x1] and y in [y0, y1] (y up), with labels.
  function axes(ctx, box, x0, x1, y0, y1, xName, yName, yDown) {
    ctx.strokeStyle = '#333'; ctx.fillStyle = '#222'; ctx.lineWidth = 1;
    ctx.font = '11px sans-serif';
    ctx.strokeRect(box.left, box.top, box.w, box.h);
    ctx.textAlign = 'center'; ctx.textBaseline = 'top';
    ticks(x0, x1, 5).forEach(function (v) {
      var px = box.left + (v - x0) / (x1 - x0) * box.w;
      ctx.beginPath(); ctx.moveTo(px, box.top + box.h); ctx.lineTo(px, box.top + box.h + 4); ctx.stroke();
      ctx.fillText(label(v), px, box.top + box.h + 6);
    });
    ctx.fillText(xName, box.left + box.w / 2, box.top + box.h + 22);
    ctx.textAlign = 'right'; ctx.textBaseline = 'middle';
    ticks(y0, y1, 5).forEach(function (v) {
      var t = (v - y0) / (y1 - y0), py = yDown ? box.top + t * box.h : box.top + box.h - t * box.h;
      ctx.beginPath(); ctx.moveTo(box.left - 4, py); ctx.lineTo(box.left, py); ctx.stroke();
      ctx.fillText(label(v), box.left - 6, py);
    });
    ctx.save(); ctx.translate(box.left - 46, box.top + box.h / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = 'center'; ctx.fillText(yName, 0, 0); ctx.restore();
  }
  // A vertical colour bar at `x` beside the box: `colour(t)` for t in [0, 1], labelled ticks.
  function colourBar(ctx, box, x, colour, tickList, name) {
    for (var py = 0; py < box.h; ++py) {
      ctx.fillStyle = colour(1 - py / (box.h - 1));
      ctx.fillRect(x, box.top + py, 14, 1);
    }
    ctx.strokeStyle = '#333'; ctx.strokeRect(x, box.top, 14, box.h);
    ctx.fillStyle = '#222'; ctx.textAlign = 'left'; ctx.textBaseline = 'middle';
    tickList.forEach(function (t) {
      var py = box.top + (1 - t.at) * box.h;
      ctx.beginPath(); ctx.moveTo(x + 14, py); ctx.lineTo(x + 18, py); ctx.stroke();
      ctx.fillText(t.text, x + 20, py);
    });
    ctx.save(); ctx.translate(x + 68, box.top + box.h / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = 'center'; ctx.fillText(name, 0, 0); ctx.restore();
  }
  // The plot box for a w_mm x h_mm field at the true aspect ratio inside the canvas's margins.
  function fit(canvas, wMm, hMm, right) {
    var left = 64, top = 28, aw = canvas.width - left - right, ah = canvas.height - top - 44;
    var s = Math.min(aw / wMm, ah / hMm);
    return { left: left, top: top, w: wMm * s, h: hMm * s };
  }

  var palette = window.VPSIM_SECTIONS ? decode(window.VPSIM_SECTIONS.palette, Uint8Array) : null;
  function paletteColour(t) {
    var k = 3 * Math.max(0, Math.min(255, Math.round(t * 255)));
    return 'rgb(' + palette[k] + ',' + palette[k + 1] + ',' + palette[k + 2] + ')';
  }
  // Clears `target` and draws a w x h field in the palette's colours into `box`, nearest pixel;
  // level(i, row) is the palette index of column i, row `row` from the top. Returns the context.
  function field(target, box, w, h, level) {
    var image = document.createElement('canvas');
    image.width = w; image.height = h;
    var ictx = image.getContext('2d'), data = ictx.createImageData(w, h);
    for (var row = 0; row < h; ++row)
      for (var i = 0; i < w; ++i) {
        var k = 3 * level(i, row), o = 4 * (row * w + i);
        data.data[o] = palette[k]; data.data[o + 1] = palette[k + 1];
        data.data[o + 2] = palette[k + 2]; data.data[o + 3] = 255;
      }
    ictx.putImageData(data, 0, 0);
    var ctx = target.getContext('2d');
    ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, target.width, target.height);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(image, box.left, box.top, box.w, box.h);
    return ctx;
  }

  var slider = document.getElementById('view3d-clip');
  var sections = window.VPSIM_SECTIONS, canvas = document.getElementById('section2d');
  if (sections && canvas) {
    var d = sections, w = d.width, h = d.height, pixels = w * h, kept = d.kept;
    var exposure = decode(d.exposure, Uint8Array), cured = decode(d.cured, Uint8Array);
    var counts = decode(d.outline_counts, Uint32Array), xy = decode(d.outline_xy, Float32Array);
    // Where each kept layer's outline starts in counts and xy.
    var outlineAt = [], ci = 0, pi = 0;
    for (var n = 0; n < kept.length; ++n) {
      outlineAt.push({ c: ci, p: pi });
      var contours = counts[ci++];
      for (var m = 0; m < contours; ++m) pi += 2 * counts[ci++];
    }
    var bytesPerLayer = Math.ceil(pixels / 8), draws = 0;
    var info = document.getElementById('section2d-label');

    var draw = function (layer) {  // layer: 1-based from the bottom
      var slot = 0;  // the kept layer nearest to it
      for (var s = 0; s < kept.length; ++s)
        if (Math.abs(kept[s] + 1 - layer) < Math.abs(kept[slot] + 1 - layer)) slot = s;
      var base = slot * pixels, wMm = w * d.pixel_mm, hMm = h * d.pixel_mm;
      var box = fit(canvas, wMm, hMm, 110);
      var ctx = field(canvas, box, w, h, function (i, row) {  // rows run down, y up
        return exposure[base + (h - 1 - row) * w + i];
      });
      var px = box.w / w;
      function X(x) { return box.left + (x - d.x0) / wMm * box.w; }
      function Y(y) { return box.top + box.h - (y - d.y0) / hMm * box.h; }
      // The model's outline of the layer (the sliced polygons, red).
      ctx.strokeStyle = '#e61e1e'; ctx.lineWidth = 1.5; ctx.beginPath();
      var at = outlineAt[slot], cc = at.c, pp = at.p, contourCount = counts[cc++];
      for (var q = 0; q < contourCount; ++q) {
        var points = counts[cc++];
        for (var r = 0; r < points; ++r, pp += 2) {
          if (r === 0) ctx.moveTo(X(xy[pp]), Y(xy[pp + 1])); else ctx.lineTo(X(xy[pp]), Y(xy[pp + 1]));
        }
        if (points) ctx.closePath();
      }
      ctx.stroke();
      // The cured region's outline: edges between cured and uncured pixels (white, dashed).
      function isCured(i, j) {
        if (i < 0 || j < 0 || i >= w || j >= h) return false;
        var b = j * w + i;
        return ((cured[slot * bytesPerLayer + (b >> 3)] >> (b & 7)) & 1) === 1;
      }
      ctx.strokeStyle = '#fff'; ctx.lineWidth = 1.5; ctx.setLineDash([4, 3]); ctx.beginPath();
      for (var cj = 0; cj <= h; ++cj)
        for (var c = 0; c <= w; ++c) {
          var here = isCured(c, cj);
          if (here !== isCured(c - 1, cj)) {
            ctx.moveTo(box.left + c * px, box.top + box.h - cj * px);
            ctx.lineTo(box.left + c * px, box.top + box.h - (cj + 1) * px);
          }
          if (here !== isCured(c, cj - 1)) {
            ctx.moveTo(box.left + c * px, box.top + box.h - cj * px);
            ctx.lineTo(box.left + (c + 1) * px, box.top + box.h - cj * px);
          }
        }
      ctx.stroke(); ctx.setLineDash([]);
      axes(ctx, box, d.x0, d.x0 + wMm, d.y0, d.y0 + hMm, 'x (mm)', 'y (mm)', false);
      var dc = d.critical / d.scale_max, barTicks = ticks(0, d.scale_max, 5).map(function (v) {
        return { at: v / d.scale_max, text: label(v) };
      }).filter(function (t) { return Math.abs(t.at - dc) > 0.05; });  // room for Dc's label
      barTicks.push({ at: dc, text: 'Dc ' + label(d.critical) });
      colourBar(ctx, box, box.left + box.w + 12, paletteColour, barTicks, 'exposure (mJ/cm²)');
      ctx.fillStyle = '#222'; ctx.textAlign = 'left'; ctx.textBaseline = 'top'; ctx.font = '12px sans-serif';
      ctx.fillText('layer ' + (kept[slot] + 1) + ' of ' + d.layers + ', x-y exposure at z = ' +
                   d.z[slot].toFixed(4) + ' mm (mid-layer)', box.left, 6);
      if (info) info.textContent = (kept[slot] + 1 !== layer ? 'layer ' + layer +
        ' is not kept; nearest kept: ' : '') + 'layer ' + (kept[slot] + 1) + '.';
      canvas.setAttribute('data-layer', String(kept[slot] + 1));
      canvas.setAttribute('data-draws', String(++draws));
      canvas.setAttribute('data-rendered', '1');
    };
    var sliderLayer = function () {
      var k = slider ? Number(slider.value) : d.layers;
      return Math.max(1, Math.min(d.layers, k));
    };
    if (slider) {
      if (Number(slider.max) <= 1) { slider.max = String(d.layers); slider.value = String(d.layers); }
      slider.addEventListener('input', function () { draw(sliderLayer()); });
    }
    draw(sliderLayer());
  }

  // The kernel I(r, z): log colour map of the Monte Carlo table, the Eq. 12 fit's contours.
  var kernel = window.VPSIM_KERNEL, kcanvas = document.getElementById('kernel2d');
  if (kernel && kcanvas && palette) {
    var nr = kernel.r_bins, nz = kernel.z_bins;
    var table = decode(kernel.intensity, Float32Array), model = decode(kernel.fit, Float32Array);
    var top = 0;
    for (var t = 0; t < table.length; ++t) top = Math.max(top, table[t]);
    var decades = 4, bottom = top * Math.pow(10, -decades);
    var rUm = nr * kernel.r_bin_um, zUm = nz * kernel.z_bin_um, kbox = fit(kcanvas, rUm, zUm, 110);
    var g = field(kcanvas, kbox, nr, nz, function (ir, iz) {  // log scale, depth down
      var v = table[iz * nr + ir];
      return v > 0 ? Math.max(0, Math.min(255, Math.round(Math.log10(v / bottom) / decades * 255))) : 0;
    });
    // The fit's contours at each decade (marching squares between bin centres, white).
    var cw = kbox.w / nr, chh = kbox.h / nz;
    function P(fr, fz) { return [kbox.left + (fr + 0.5) * cw, kbox.top + (fz + 0.5) * chh]; }
    g.strokeStyle = '#fff'; g.lineWidth = 1.2; g.beginPath();
    for (var e = 1; e < decades; ++e) {
      var level = bottom * Math.pow(10, e);
      for (var jz = 0; jz + 1 < nz; ++jz)
        for (var jr = 0; jr + 1 < nr; ++jr) {
          var a = model[jz * nr + jr], b = model[jz * nr + jr + 1];
          var c2 = model[(jz + 1) * nr + jr + 1], d2 = model[(jz + 1) * nr + jr];
          var cut = [];  // where the level crosses the cell's four edges
          if ((a >= level) !== (b >= level)) cut.push(P(jr + (level - a) / (b - a), jz));
          if ((b >= level) !== (c2 >= level)) cut.push(P(jr + 1, jz + (level - b) / (c2 - b)));
          if ((d2 >= level) !== (c2 >= level)) cut.push(P(jr + (level - d2) / (c2 - d2), jz + 1));
          if ((a >= level) !== (d2 >= level)) cut.push(P(jr, jz + (level - a) / (d2 - a)));
          for (var u = 0; u + 1 < cut.length; u += 2) {
            g.moveTo(cut[u][0], cut[u][1]); g.lineTo(cut[u + 1][0], cut[u + 1][1]);
          }
        }
    }
    g.stroke();
    // Where the fit starts (zmax): above it the fit is not meant to hold (dashed).
    var zStart = kbox.top + kernel.fit_depth_start_um / zUm * kbox.h;
    g.setLineDash([5, 4]); g.strokeStyle = '#e61e1e'; g.beginPath();
    g.moveTo(kbox.left, zStart); g.lineTo(kbox.left + kbox.w, zStart); g.stroke(); g.setLineDash([]);
    axes(g, kbox, 0, rUm, 0, zUm, 'r (µm)', 'depth (µm)', true);
    var kt = [];
    for (var dd = 0; dd <= decades; ++dd)
      kt.push({ at: dd / decades, text: (bottom * Math.pow(10, dd)).toPrecision(2) });
    colourBar(g, kbox, kbox.left + kbox.w + 12, paletteColour, kt, 'I (mW/mm², log)');
    g.fillStyle = '#222'; g.textAlign = 'left'; g.textBaseline = 'top'; g.font = '12px sans-serif';
    g.fillText('I(r, z), Monte Carlo; white: Eq. 12 fit at each decade', kbox.left, 6);
    kcanvas.setAttribute('data-rendered', '1');
  }

  var wanted = /layer=(\d+)/.exec(window.location.hash);
  if (wanted && slider) {
    slider.value = wanted[1];
    slider.dispatchEvent(new Event('input'));
  }
})();
