// The script of the page `nrsfm view` writes (tools/view_page.h describes
// the data and the URL fragment). Plain ES5 so that old browsers run it too;
// three.js r111, its OrbitControls and viewer_util.js are inlined before it.
(function () {
  'use strict';

  var data = JSON.parse(document.getElementById('nrsfm-data').textContent);
  var meta = data.meta;
  var F = meta.num_frames, M = meta.num_cameras, P = meta.num_points;
  var edges = data.edges;
  var COLOR = {
    estimate: '#1f5fbf', estimateEdge: '#7a9fd9', truth: '#e07b00', truthEdge: '#f0b060',
    error3d: '#c03030', track: '#1a9641', reprojection: '#1f5fbf', residual: '#d7191c',
    missing: '#999999', rms: '#1a9641'
  };
  var FPS_CHOICES = [1, 2, 5, 10, 25, 50, 100];

  var state = {
    frame: 0, playing: false, fps: 25, camera: 0, truth: true, edges: true, residuals: true,
    vUp: false, std: !!data.point_std
  };
  var timer = null;

  var util = nrsfmViewerUtil;
  var $ = util.$, format = util.format, fragment = util.fragment, intIn = util.intIn,
      message = util.message, discTexture = util.discTexture, overlay = util.overlay;

  // The colour scale of the predicted standard deviation (points_covariance.csv):
  // viridis from its 5th to its 95th percentile over the sequence, clamped, so
  // that one badly determined point does not wash out the rest and a frame's
  // colours compare with every other frame's.
  var stdScale = data.point_std ? {
    low: util.quantile(data.point_std, 0.05), high: util.quantile(data.point_std, 0.95)
  } : null;
  function stdColour(s) {
    var span = stdScale.high - stdScale.low;
    return util.viridis(span > 0 ? (s - stdScale.low) / span : 0.5);
  }

  // ---- 3D view (three.js) ----
  // The camera frame is right-handed with x, y along the image's u, v. With v
  // down (images) z points away from the viewer, and the camera frame maps to
  // three.js (y up, the view looking along -z) as (x, -y, -z); with v up
  // (e.g. motion capture projected with y up) z points towards the viewer and
  // the map is the identity. Both are rotations, so the 3D view is never
  // mirrored, and the first view looks through camera 0 as the 2D view does.
  var three = null;

  function makePoints(scene, color, size, texture) {
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * P), 3));
    var material = new THREE.PointsMaterial({
      color: color, size: size, sizeAttenuation: false, map: texture, alphaTest: 0.5
    });
    var points = new THREE.Points(geometry, material);
    points.frustumCulled = false;
    scene.add(points);
    return points;
  }

  function makeLines(scene, color, count) {
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * count), 3));
    var lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({color: color}));
    lines.frustumCulled = false;
    scene.add(lines);
    return lines;
  }

  // Largest distance of a point from the (per-frame) centre over the sequence.
  function radius() {
    var r = 0;
    var arrays = [data.estimate].concat(data.truth ? [data.truth] : []);
    arrays.forEach(function (a) {
      for (var i = 0; i < a.length; i += 3) {
        r = Math.max(r, Math.sqrt(a[i] * a[i] + a[i + 1] * a[i + 1] + a[i + 2] * a[i + 2]));
      }
    });
    return r > 0 ? r : 1;
  }

  function setup3d() {
    var container = $('view3d');
    if (typeof THREE === 'undefined') {
      message(container, 'three.js did not load: the 3D view cannot be drawn.');
      return;
    }
    var renderer;
    try {
      renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    } catch (e) {
      message(container, 'This browser has no WebGL, so the 3D view cannot be drawn; ' +
              'the 2D view and the error plot still work.');
      return;
    }
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xffffff, 1);
    container.appendChild(renderer.domElement);
    var scene = new THREE.Scene();
    var r = radius();
    var camera = new THREE.PerspectiveCamera(30, 1, r / 100, r * 100);
    // Through camera 0, or turned by orbit=A,E: azimuth A about the vertical
    // and elevation E, in degrees.
    var distance = 1.1 * r / Math.tan(15 * Math.PI / 180);
    var orbit = (fragment().orbit || '0,0').split(',').map(parseFloat);
    var azimuth = (orbit[0] || 0) * Math.PI / 180, elevation = (orbit[1] || 0) * Math.PI / 180;
    camera.position.set(distance * Math.cos(elevation) * Math.sin(azimuth),
                        distance * Math.sin(elevation),
                        distance * Math.cos(elevation) * Math.cos(azimuth));
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.set(0, 0, 0);
    controls.enablePan = true;
    controls.update();
    var texture = discTexture();
    three = {renderer: renderer, scene: scene, camera: camera, controls: controls};
    if (data.truth) {
      three.truthEdges = overlay(makeLines(scene, COLOR.truthEdge, edges.length));
      three.truth = overlay(makePoints(scene, COLOR.truth, 11, texture));
      three.errors = overlay(makeLines(scene, COLOR.error3d, P));
    }
    three.estimateEdges = makeLines(scene, COLOR.estimateEdge, edges.length);
    three.estimate = makePoints(scene, COLOR.estimate, 6, texture);
    if (data.point_std) {
      // The same points coloured by their predicted std (white times the
      // vertex colour), drawn instead of the plain ones while state.std.
      three.estimateStd = makePoints(scene, '#ffffff', 8, texture);
      three.estimateStd.geometry.setAttribute(
          'color', new THREE.BufferAttribute(new Float32Array(3 * P), 3));
      three.estimateStd.material.vertexColors = THREE.VertexColors;
    }
    controls.addEventListener('change', render3d);
  }

  // A point the reconstruction left out is null: NaN, which WebGL does not draw.
  function toThree(array, t, p, out, o) {
    var i = 3 * (t * P + p), sign = state.vUp ? 1 : -1;
    var missing = array[i] === null;
    out[o] = missing ? NaN : array[i];
    out[o + 1] = missing ? NaN : sign * array[i + 1];
    out[o + 2] = missing ? NaN : sign * array[i + 2];
  }

  function fillPoints(points, array, t) {
    var out = points.geometry.attributes.position.array;
    for (var p = 0; p < P; ++p) toThree(array, t, p, out, 3 * p);
    points.geometry.attributes.position.needsUpdate = true;
  }

  function fillEdges(lines, array, t) {
    var out = lines.geometry.attributes.position.array;
    for (var e = 0; e < edges.length; ++e) {
      toThree(array, t, edges[e][0], out, 6 * e);
      toThree(array, t, edges[e][1], out, 6 * e + 3);
    }
    lines.geometry.attributes.position.needsUpdate = true;
  }

  function update3d() {
    if (!three) return;
    var t = state.frame;
    fillPoints(three.estimate, data.estimate, t);
    fillEdges(three.estimateEdges, data.estimate, t);
    if (three.estimateStd) {
      fillPoints(three.estimateStd, data.estimate, t);
      var colours = three.estimateStd.geometry.attributes.color.array;
      for (var q = 0; q < P; ++q) {
        var s = data.point_std[t * P + q];
        var rgb = s === null ? [0.6, 0.6, 0.6] : stdColour(s);
        colours[3 * q] = rgb[0];
        colours[3 * q + 1] = rgb[1];
        colours[3 * q + 2] = rgb[2];
      }
      three.estimateStd.geometry.attributes.color.needsUpdate = true;
      three.estimateStd.visible = state.std;
      three.estimate.visible = !state.std;
    }
    three.estimateEdges.visible = state.edges;
    if (three.truth) {
      fillPoints(three.truth, data.truth, t);
      fillEdges(three.truthEdges, data.truth, t);
      var out = three.errors.geometry.attributes.position.array;
      for (var p = 0; p < P; ++p) {
        toThree(data.estimate, t, p, out, 6 * p);
        toThree(data.truth, t, p, out, 6 * p + 3);
      }
      three.errors.geometry.attributes.position.needsUpdate = true;
      three.truth.visible = state.truth;
      three.truthEdges.visible = state.truth && state.edges;
      three.errors.visible = state.truth && state.residuals;
    }
    render3d();
  }

  function resize3d() {
    if (!three) return;
    var container = $('view3d');
    var w = Math.max(1, container.clientWidth), h = Math.max(1, container.clientHeight);
    three.renderer.setSize(w, h, false);
    three.camera.aspect = w / h;
    three.camera.updateProjectionMatrix();
  }

  function render3d() {
    if (three) three.renderer.render(three.scene, three.camera);
  }

  // ---- 2D view (canvas): tracks, reprojections, residuals ----
  var bounds2d = [];  // per camera: {u0, v0, u1, v1}

  function uv(array, t, c, p) {
    var i = 2 * ((t * M + c) * P + p);
    return [array[i], array[i + 1]];
  }

  function computeBounds() {
    for (var c = 0; c < M; ++c) {
      var b = {u0: Infinity, v0: Infinity, u1: -Infinity, v1: -Infinity};
      [data.reprojection, data.tracks].forEach(function (a) {
        if (!a) return;
        for (var t = 0; t < F; ++t) {
          for (var p = 0; p < P; ++p) {
            var w = uv(a, t, c, p);
            if (w[0] === null || w[1] === null) continue;
            b.u0 = Math.min(b.u0, w[0]); b.u1 = Math.max(b.u1, w[0]);
            b.v0 = Math.min(b.v0, w[1]); b.v1 = Math.max(b.v1, w[1]);
          }
        }
      });
      if (!(b.u1 > b.u0)) { b.u0 -= 1; b.u1 += 1; }
      if (!(b.v1 > b.v0)) { b.v0 -= 1; b.v1 += 1; }
      bounds2d.push(b);
    }
  }

  // The frames under the 2D view (nrsfm view --frames_dir): one image per
  // frame, decoded by the browser; the view's extent grows to the image's
  // once the first one is loaded (pixel centres at integer u, v).
  var frameImages = null, frameSizeKnown = false;
  function loadFrames() {
    if (!data.frames) return;
    frameImages = data.frames.map(function (src) {
      var image = new Image();
      image.onload = function () {
        if (!frameSizeKnown) {
          frameSizeKnown = true;
          var b = bounds2d[0];
          b.u0 = Math.min(b.u0, -0.5); b.v0 = Math.min(b.v0, -0.5);
          b.u1 = Math.max(b.u1, image.naturalWidth - 0.5);
          b.v1 = Math.max(b.v1, image.naturalHeight - 0.5);
        }
        draw2d();
      };
      image.src = src;
      return image;
    });
  }

  function draw2d() {
    var canvas = $('view2d');
    var ratio = window.devicePixelRatio || 1;
    var w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
    if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
      canvas.width = Math.round(w * ratio);
      canvas.height = Math.round(h * ratio);
    }
    $('title2d').textContent = '2D: camera image (u right, v ' + (state.vUp ? 'up' : 'down') +
        ')' + (data.tracks ? '' : ' - the 2D tracks were not given (--input): reprojections only');
    var g = canvas.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    var t = state.frame, c = state.camera, b = bounds2d[c];
    // u to the right, v down, as in the image; one scale for both axes.
    // The whole sequence's extent fills the pane below the caption line.
    var margin = 16, top = 24;
    var s = Math.min((w - 2 * margin) / (b.u1 - b.u0), (h - top - margin) / (b.v1 - b.v0));
    var ou = margin + ((w - 2 * margin) - s * (b.u1 - b.u0)) / 2 - s * b.u0;
    var ov = ((h - top - margin) - s * (b.v1 - b.v0)) / 2 - s * b.v0;
    function px(w2) {
      var y = ov + s * w2[1];
      return [ou + s * w2[0], state.vUp ? h - margin - y : top + y];
    }
    var i, p, a, q;
    var image = frameImages && state.camera === 0 ? frameImages[t] : null;
    if (image && image.complete && image.naturalWidth > 0) {
      // The image's corners, at pixel edges -0.5 and size - 0.5.
      a = px([-0.5, -0.5]);
      q = px([image.naturalWidth - 0.5, image.naturalHeight - 0.5]);
      g.save();
      g.translate(a[0], a[1]);
      g.scale((q[0] - a[0]) / image.naturalWidth, (q[1] - a[1]) / image.naturalHeight);
      g.globalAlpha = 0.8;
      g.drawImage(image, 0, 0);
      g.restore();
    }
    if (state.edges) {
      g.strokeStyle = COLOR.estimateEdge;
      g.lineWidth = 1;
      g.beginPath();
      for (i = 0; i < edges.length; ++i) {
        a = uv(data.reprojection, t, c, edges[i][0]);
        q = uv(data.reprojection, t, c, edges[i][1]);
        if (a[0] === null || q[0] === null) continue;  // left out
        a = px(a);
        q = px(q);
        g.moveTo(a[0], a[1]);
        g.lineTo(q[0], q[1]);
      }
      g.stroke();
    }
    var visible = [];
    for (p = 0; p < P; ++p) {
      var track = data.tracks ? uv(data.tracks, t, c, p) : [null, null];
      visible.push(track[0] !== null && track[1] !== null);
      q = uv(data.reprojection, t, c, p);
      if (visible[p] && state.residuals && q[0] !== null) {
        a = px(track);
        q = px(q);
        g.strokeStyle = COLOR.residual;
        g.lineWidth = 1.5;
        g.beginPath();
        g.moveTo(a[0], a[1]);
        g.lineTo(q[0], q[1]);
        g.stroke();
      }
    }
    // Tracks as rings around the reprojections' dots, so both show when they
    // coincide.
    for (p = 0; p < P; ++p) {
      if (!visible[p]) continue;
      a = px(uv(data.tracks, t, c, p));
      g.strokeStyle = COLOR.track;
      g.lineWidth = 1.5;
      g.beginPath();
      g.arc(a[0], a[1], 5, 0, 2 * Math.PI);
      g.stroke();
    }
    for (p = 0; p < P; ++p) {
      a = uv(data.reprojection, t, c, p);
      if (a[0] === null) continue;  // left out of the reconstruction
      a = px(a);
      g.fillStyle = (data.tracks && !visible[p]) ? COLOR.missing : COLOR.reprojection;
      g.beginPath();
      g.arc(a[0], a[1], 2.5, 0, 2 * Math.PI);
      g.fill();
    }
    g.fillStyle = '#444';
    g.font = '12px sans-serif';
    var text = 'frame ' + t + ', camera ' + c;
    if (data.frame_reprojection_rms) {
      text += ': reprojection RMS ' + format(data.frame_reprojection_rms[t], 4);
    } else {
      text += ': no 2D tracks given (--input); reprojections only';
    }
    g.fillText(text, 6, 14);
  }

  // ---- per-frame error plot ----
  // The median predicted std of each frame's points (null when none).
  var frameStd = data.point_std ? (function () {
    var out = [];
    for (var t = 0; t < F; ++t) out.push(util.quantile(data.point_std.slice(t * P, (t + 1) * P), 0.5));
    return out;
  })() : null;

  function plotSeries() {
    var series = [];
    if (data.frame_error) {
      series.push({values: data.frame_error, color: COLOR.error3d, name: '3D error (e3D term)'});
    }
    if (data.frame_reprojection_rms) {
      series.push({values: data.frame_reprojection_rms, color: COLOR.rms,
                   name: 'reprojection RMS'});
    }
    if (frameStd) {
      series.push({values: frameStd, color: util.cssColour(util.viridis(0.15)),
                   name: 'median predicted std'});
    }
    return series;
  }

  function drawPlot() {
    var canvas = $('plot');
    var ratio = window.devicePixelRatio || 1;
    var w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
    if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
      canvas.width = Math.round(w * ratio);
      canvas.height = Math.round(h * ratio);
    }
    var g = canvas.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    g.font = '11px sans-serif';
    var left = 8, right = w - 8, top = 18, bottom = h - 8;
    function x(t) { return left + (F > 1 ? t / (F - 1) : 0.5) * (right - left); }
    var series = plotSeries();
    if (series.length === 0) {
      g.fillStyle = '#777';
      g.fillText('no per-frame error: give --truth for the 3D error, --input for the ' +
                 'reprojection error', left, top + 12);
    }
    var label = left;
    series.forEach(function (s) {
      var max = 0;
      s.values.forEach(function (v) { if (v !== null && v > max) max = v; });
      if (!(max > 0)) max = 1;
      g.strokeStyle = s.color;
      g.lineWidth = 1.25;
      g.beginPath();
      var pen = false;
      for (var t = 0; t < F; ++t) {
        var v = s.values[t];
        if (v === null) { pen = false; continue; }
        var y = bottom - (v / max) * (bottom - top);
        if (pen) g.lineTo(x(t), y); else g.moveTo(x(t), y);
        pen = true;
      }
      g.stroke();
      g.fillStyle = s.color;
      var text = s.name + ' (top = ' + format(max, 3) + '), frame ' + state.frame + ': ' +
                 format(s.values[state.frame], 4);
      g.fillText(text, label, 12);
      label += g.measureText(text).width + 24;
    });
    g.strokeStyle = '#222';
    g.lineWidth = 1;
    g.beginPath();
    g.moveTo(x(state.frame), top - 4);
    g.lineTo(x(state.frame), bottom);
    g.stroke();
    canvas.onclick = function (event) {
      var rect = canvas.getBoundingClientRect();
      var f = (event.clientX - rect.left - left) / (right - left);
      setFrame(Math.round(Math.min(1, Math.max(0, f)) * (F - 1)));
    };
  }

  // ---- frame, playback, controls ----
  function setFrame(t) {
    state.frame = Math.min(F - 1, Math.max(0, t));
    $('slider').value = String(state.frame);
    var text = 'frame ' + state.frame + ' / ' + (F - 1);
    if (data.frame_error) text += ', 3D error ' + format(data.frame_error[state.frame], 3);
    $('frame-label').textContent = text;
    document.title = 'nrsfm view: frame ' + state.frame + ' of ' + F;
    update3d();
    draw2d();
    drawPlot();
  }

  function setPlaying(playing) {
    state.playing = playing;
    $('play').textContent = playing ? 'Pause' : 'Play';
    if (timer !== null) clearInterval(timer);
    timer = null;
    if (playing) {
      timer = setInterval(function () { setFrame((state.frame + 1) % F); }, 1000 / state.fps);
    }
  }

  function setupControls() {
    var slider = $('slider');
    slider.max = String(F - 1);
    slider.addEventListener('input', function () { setFrame(parseInt(slider.value, 10)); });
    $('play').addEventListener('click', function () { setPlaying(!state.playing); });
    var fps = $('fps');
    FPS_CHOICES.forEach(function (n) {
      var option = document.createElement('option');
      option.value = String(n);
      option.textContent = n + ' frames/s';
      fps.appendChild(option);
    });
    fps.value = String(state.fps);
    fps.addEventListener('change', function () {
      state.fps = parseInt(fps.value, 10);
      if (state.playing) setPlaying(true);
    });
    if (M > 1) {
      $('camera-choice').hidden = false;
      for (var c = 0; c < M; ++c) {
        var option = document.createElement('option');
        option.value = String(c);
        option.textContent = String(c);
        $('camera').appendChild(option);
      }
      $('camera').addEventListener('change', function () {
        state.camera = parseInt($('camera').value, 10);
        draw2d();
      });
    }
    [['show-truth', 'truth'], ['show-edges', 'edges'], ['show-residuals', 'residuals'],
     ['v-up', 'vUp'], ['show-std', 'std']]
        .forEach(function (pair) {
          $(pair[0]).addEventListener('change', function () {
            state[pair[1]] = $(pair[0]).checked;
            update3d();
            draw2d();
          });
        });
    if (!data.truth) $('show-truth').parentNode.hidden = true;
    if (!data.point_std) $('show-std').parentNode.hidden = true;
    $('show-std').checked = state.std;
    document.addEventListener('keydown', function (event) {
      if (event.target && event.target.tagName === 'SELECT') return;
      if (event.key === ' ') { setPlaying(!state.playing); event.preventDefault(); }
      if (event.key === 'ArrowRight') setFrame(state.frame + 1);
      if (event.key === 'ArrowLeft') setFrame(state.frame - 1);
    });
  }

  // ---- text: summary, legends, details ----
  function legend(id, items) {
    var div = $(id);
    items.forEach(function (item) {
      var swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = item[0];
      div.appendChild(swatch);
      div.appendChild(document.createTextNode(item[1]));
    });
  }

  function setupText() {
    var m = meta.metrics;
    // A perspective answer is fixed up to scale: it is scored with one global
    // scale (e3d_scaled), and the truth and per-frame errors are shown so.
    var scaled = meta.camera_model === 'perspective';
    var e3dText = m ? (scaled ? 'e3D with one scale ' + format(m.e3d_scaled, 4)
                              : 'e3D ' + format(m.e3d, 4)) : '';
    $('summary').textContent = meta.result + ': F = ' + F + ', M = ' + M + ', P = ' + P +
        (meta.num_bases >= 0 ? ', K = ' + meta.num_bases : '') +
        (m ? ', ' + e3dText : '') +
        (meta.reprojection_rms !== undefined ? ', reprojection RMS ' +
         format(meta.reprojection_rms, 4) : '');
    $('title3d').textContent = '3D: ' + meta.scoring_frame + ', each frame centred' +
        (data.truth ? '; truth aligned as for e3D (one orthogonal map for all frames)' : '') +
        '. Drag to orbit, wheel to zoom, right-drag to pan.';
    var items3d = [[COLOR.estimate, 'reconstruction']];
    if (data.truth) items3d.push([COLOR.truth, 'truth'], [COLOR.error3d, '3D error']);
    legend('legend3d', items3d);
    if (stdScale) {
      // The std scale: its two ends and middle, in the units of the tracks.
      var mid = 0.5 * (stdScale.low + stdScale.high);
      legend('legend3d', [
        [util.cssColour(util.viridis(0)), 'predicted std ' + format(stdScale.low, 3) + ' or less'],
        [util.cssColour(util.viridis(0.5)), format(mid, 3)],
        [util.cssColour(util.viridis(1)), format(stdScale.high, 3) + ' or more (input units)']
      ]);
    }
    var items2d = [[COLOR.reprojection, 'reprojection']];
    if (data.tracks) {
      items2d.unshift([COLOR.track, 'track']);
      items2d.push([COLOR.residual, 'residual'], [COLOR.missing, 'reprojection of a missing point']);
    }
    legend('legend2d', items2d);

    var banner = [];
    if (!meta.solution_usable) {
      banner.push('result.json marks this solution as NOT usable: it holds the start, ' +
                  'not a refined reconstruction.');
    }
    if (banner.length) {
      $('banner').textContent = banner.join(' ');
      $('banner').hidden = false;
    }
    var rows = [
      ['result', meta.result],
      ['ground truth', meta.truth || 'not given'],
      ['2D tracks', meta.input || 'not given'],
      ['size', F + ' frames, ' + M + ' camera(s), ' + P + ' points' +
               (meta.num_bases >= 0 ? ', K = ' + meta.num_bases : '')],
      ['3D frame', meta.scoring_frame],
      ['camera', meta.camera_model === 'perspective'
          ? 'perspective (pinhole, result.json intrinsics)' : 'weak perspective']
    ];
    if (m) {
      rows.push(['metrics', 'e3D ' + format(m.e3d, 6) +
                 (scaled ? ', with one scale ' + format(m.e3d_scaled, 6) : '') + ', frob_zsign ' +
                 format(m.frob_zsign, 6) + ', 3D error ' + format(m.error3d_pct, 4) +
                 ' %, z error ' + format(m.zerror_pct, 4) + ' %']);
    }
    if (meta.reprojection_rms !== undefined) {
      rows.push(['reprojection RMS', format(meta.reprojection_rms, 6) + ' (input units)']);
    }
    if (meta.start_used) rows.push(['start', meta.start_used]);
    if (stdScale) {
      rows.push(['predicted std', 'median ' + format(util.quantile(data.point_std, 0.5), 4) +
                 ', 95th percentile ' + format(stdScale.high, 4) + ', largest ' +
                 format(util.quantile(data.point_std, 1), 4) + ' (input units; sqrt of the ' +
                 'trace of each point\'s covariance, points_covariance.csv, as result.json)']);
    }
    rows.push(['solution usable', meta.solution_usable ? 'yes' : 'NO']);
    rows.push(['edges', edges.length + ' from ' + meta.edge_source]);
    meta.warnings.forEach(function (w) { rows.push(['warning', w]); });
    meta.notes.forEach(function (n) { rows.push(['note', n]); });
    rows.push(['drawn with', 'three.js r' + (typeof THREE !== 'undefined' ? THREE.REVISION : '?')]);
    var info = $('info');
    rows.forEach(function (row) {
      var dt = document.createElement('dt');
      dt.textContent = row[0];
      var dd = document.createElement('dd');
      dd.textContent = row[1];
      info.appendChild(dt);
      info.appendChild(dd);
    });
  }

  // Where the panes are, for tests that look at screenshots.
  function recordLayout() {
    function rect(element) {
      var r = element.getBoundingClientRect();
      return [r.left, r.top, r.width, r.height].map(Math.round).join(' ');
    }
    document.body.setAttribute('data-view3d', rect($('view3d')));
    document.body.setAttribute('data-view2d', rect($('view2d')));
  }

  function applyFragment() {
    var f = fragment();
    var n;
    if ((n = intIn(f.fps, 1, 1000)) !== null) {
      state.fps = n;
      $('fps').value = String(n);
    }
    if (M > 1 && (n = intIn(f.camera, 0, M - 1)) !== null) {
      state.camera = n;
      $('camera').value = String(n);
    }
    setFrame((n = intIn(f.frame, 0, F - 1)) !== null ? n : state.frame);
    if (f.vup === '1' || f.vup === '0') {
      state.vUp = f.vup === '1';
      $('v-up').checked = state.vUp;
      setFrame(state.frame);
    }
    if (data.point_std && (f.std === '1' || f.std === '0')) {
      state.std = f.std === '1';
      $('show-std').checked = state.std;
      setFrame(state.frame);
    }
    if (f.play === '1') setPlaying(true);
    if ((n = intIn(f.slide_to, 0, F - 1)) !== null) {
      var slider = $('slider');
      slider.value = String(n);
      slider.dispatchEvent(new Event('input', {bubbles: true}));
    }
  }

  computeBounds();
  loadFrames();
  setupText();
  setupControls();
  setup3d();
  resize3d();
  recordLayout();
  applyFragment();
  window.addEventListener('resize', function () {
    resize3d();
    recordLayout();
    setFrame(state.frame);
  });
  window.addEventListener('hashchange', applyFragment);
})();
