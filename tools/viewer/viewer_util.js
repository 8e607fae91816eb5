// Helpers of the `nrsfm view` page's script (tools/viewer/viewer.js, which
// follows this file in the page): DOM lookup, number formatting, the URL
// fragment, a bounded integer, an error message box, the points' disc
// texture, the truth's overlay drawing, a quantile and the colour scale of
// the predicted standard deviation. Plain ES5, as viewer.js.
var nrsfmViewerUtil = (function () {
  'use strict';

  function $(id) { return document.getElementById(id); }

  function format(value, digits) {
    return (value === null || value === undefined) ? 'n/a' : Number(value).toPrecision(digits);
  }

  // ---- URL fragment: #frame=N&play=1&fps=N&camera=C&vup=1&std=0|1&orbit=A,E&slide_to=N ----
  function fragment() {
    var out = {};
    location.hash.replace(/^#/, '').split('&').forEach(function (item) {
      if (!item) return;
      var i = item.indexOf('=');
      var key = decodeURIComponent(i < 0 ? item : item.slice(0, i));
      out[key] = i < 0 ? '' : decodeURIComponent(item.slice(i + 1));
    });
    return out;
  }

  function intIn(text, lo, hi) {
    var n = parseInt(text, 10);
    if (isNaN(n)) return null;
    return Math.min(hi, Math.max(lo, n));
  }

  function message(container, text) {
    var div = document.createElement('div');
    div.className = 'message';
    div.textContent = text;
    container.appendChild(div);
  }

  function discTexture() {
    var canvas = document.createElement('canvas');
    canvas.width = canvas.height = 64;
    var g = canvas.getContext('2d');
    g.fillStyle = '#fff';
    g.beginPath();
    g.arc(32, 32, 30, 0, 2 * Math.PI);
    g.fill();
    return new THREE.CanvasTexture(canvas);
  }

  // The truth is an overlay: it writes no depth and is drawn first, so the
  // reconstruction drawn after it is never hidden by it where they nearly
  // coincide; its larger discs show as rings around the reconstruction's.
  function overlay(object) {
    object.material.depthWrite = false;
    object.renderOrder = -1;
    return object;
  }

  // The q-quantile (0 ≤ q ≤ 1, nearest rank) of the finite values of `values`
  // (null counts as missing); null when there is none.
  function quantile(values, q) {
    var finite = values.filter(function (v) { return v !== null && isFinite(v); });
    if (finite.length === 0) return null;
    finite.sort(function (a, b) { return a - b; });
    return finite[Math.min(finite.length - 1, Math.max(0, Math.round(q * (finite.length - 1))))];
  }

  // Viridis (perceptually uniform, colour-blind safe) at s in [0, 1], as
  // [r, g, b] in [0, 1]: dark purple (low) through teal to yellow (high).
  var VIRIDIS = [[0x44, 0x01, 0x54], [0x3b, 0x52, 0x8b], [0x21, 0x91, 0x8c],
                 [0x5e, 0xc9, 0x62], [0xfd, 0xe7, 0x25]];
  function viridis(s) {
    var x = Math.min(1, Math.max(0, s)) * (VIRIDIS.length - 1);
    var i = Math.min(VIRIDIS.length - 2, Math.floor(x)), f = x - i;
    return [0, 1, 2].map(function (c) {
      return (VIRIDIS[i][c] + f * (VIRIDIS[i + 1][c] - VIRIDIS[i][c])) / 255;
    });
  }
  function cssColour(rgb) {
    return 'rgb(' + rgb.map(function (c) { return Math.round(255 * c); }).join(',') + ')';
  }

  return {
    $: $, format: format, fragment: fragment, intIn: intIn, message: message,
    discTexture: discTexture, overlay: overlay, quantile: quantile, viridis: viridis,
    cssColour: cssColour
  };
})();
