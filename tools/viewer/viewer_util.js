// Helpers of the `nrsfm view` page's script (tools/viewer/viewer.js, which
// follows this file in the page): DOM lookup, number formatting, the URL
// fragment, a bounded integer, an error message box, the points' disc
// texture and the truth's overlay drawing. Plain ES5, as viewer.js.
var nrsfmViewerUtil = (function () {
  'use strict';

  function $(id) { return document.getElementById(id); }

  function format(value, digits) {
    return (value === null || value === undefined) ? 'n/a' : Number(value).toPrecision(digits);
  }

  // ---- URL fragment: #frame=N&play=1&fps=N&camera=C&vup=1&orbit=A,E&slide_to=N ----
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

  return {
    $: $, format: format, fragment: fragment, intIn: intIn, message: message,
    discTexture: discTexture, overlay: overlay
  };
})();
