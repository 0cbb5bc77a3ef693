// The report's 3D view (see view3d.rs): an orthographic projection of the hoses (lines
// as wide as the tube, painter-sorted) and the environment outlines into the inline
// SVG #v3d-svg. Drag to turn, shift-drag to pan, wheel to zoom; presets and the
// colour quantity from the controls. The first frame is drawn by strand itself with
// the same formulas, so the page shows it without scripts too.
(function () {
  "use strict";
  var svg = document.getElementById("v3d-svg");
  var dataNode = document.getElementById("v3d-data");
  if (!svg || !dataNode) { return; }
  var D = JSON.parse(dataNode.textContent);
  var NS = "http://www.w3.org/2000/svg";
  var scene = document.getElementById("v3d-scene");
  var readout = document.getElementById("v3d-readout");
  var state = { yaw: D.view.yaw, pitch: D.view.pitch, zoom: 1, panX: 0, panY: 0,
    quantity: D.view.quantity, run: 0,
    // Results drawn as outlines behind the shown one: the reference at first.
    overlay: D.runs.map(function (r, k) { return k === 0; }) };
  var VIRIDIS = D.viridis;

  // The viridis colour of t in [0, 1]; magenta where there is no value (null).
  function colour(t) {
    if (t === null || !isFinite(t)) { return "#ff00ff"; }
    t = Math.min(1, Math.max(0, t));
    var x = t * (VIRIDIS.length - 1);
    var i = Math.min(Math.floor(x), VIRIDIS.length - 2);
    var f = x - i;
    var hex = "#";
    for (var k = 0; k < 3; k++) {
      var c = Math.round(VIRIDIS[i][k] + f * (VIRIDIS[i + 1][k] - VIRIDIS[i][k]));
      hex += (c < 16 ? "0" : "") + c.toString(16);
    }
    return hex;
  }

  // Screen right u, up v and depth d (into the screen) for yaw a, pitch e (degrees).
  function axes(yaw, pitch) {
    var a = yaw * Math.PI / 180, e = pitch * Math.PI / 180;
    var u = [Math.cos(a), Math.sin(a), 0];
    var w = [-Math.sin(a), Math.cos(a), 0];
    var v = [Math.sin(e) * w[0], Math.sin(e) * w[1], Math.cos(e)];
    var d = [Math.cos(e) * w[0], Math.cos(e) * w[1], -Math.sin(e)];
    return { u: u, v: v, d: d };
  }

  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

  // The grey of a surface polygon under a head light along d (see view3d.rs), or null
  // for a polygon without area.
  function shade(poly, d) {
    var n = [0, 0, 0];
    for (var i = 0; i < poly.length; i++) {
      var a = poly[i], b = poly[(i + 1) % poly.length];
      n[0] += (a[1] - b[1]) * (a[2] + b[2]);
      n[1] += (a[2] - b[2]) * (a[0] + b[0]);
      n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    var length = Math.sqrt(dot(n, n));
    if (!(length > 0)) { return null; }
    var light = Math.abs(dot(n, d) / length);
    function level(base) {
      var c = Math.round(base * (0.55 + 0.45 * light));
      return (c < 16 ? "0" : "") + c.toString(16);
    }
    return "#" + level(196) + level(204) + level(214);
  }

  function fmt(x) { return x.toFixed(2); }

  // Vertex j's value of quantity q, or null (JSON has null for a non-finite value and
  // for a straight vertex's bend radius).
  function value(rod, q, j) {
    var a = rod[q];
    return a && typeof a[j] === "number" ? a[j] : null;
  }

  // The colour parameter in [0, 1] of edge j (mean of its vertices; bend radius and
  // clearance: the tighter vertex, tight = 1, straight or out of reach = 0), or null.
  function edgeT(rod, q, j) {
    var r = D.ranges[q];
    var lo = r[0], hi = r[1];
    var a = value(rod, q, j - 1), b = value(rod, q, j);
    if (q === "rb" || q === "c") {
      var tight = a === null ? b : (b === null ? a : Math.min(a, b));
      if (tight === null) { return 0; }
      return hi > lo ? 1 - (Math.min(tight, hi) - lo) / (hi - lo) : 1;
    }
    if (a === null || b === null) { return null; }
    return hi > lo ? (0.5 * (a + b) - lo) / (hi - lo) : 0;
  }

  function el(name, attrs) {
    var n = document.createElementNS(NS, name);
    for (var k in attrs) { n.setAttribute(k, attrs[k]); }
    return n;
  }

  function draw() {
    var ax = axes(state.yaw, state.pitch);
    var s = D.view.scale * state.zoom;
    var cx = D.view.width / 2 + state.panX, cy = D.view.height / 2 + state.panY;
    var c = D.view.centre;
    function at(p) {
      var q = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
      return [cx + s * dot(ax.u, q), cy - s * dot(ax.v, q), dot(ax.d, q)];
    }
    var items = [];
    var run = D.runs[state.run];
    // A part that moved with the shown result (a motion's pose) is drawn where it is.
    var env = D.env.map(function (mesh) {
      var own = (run.env || []).filter(function (m) { return m.name === mesh.name; })[0];
      return own || mesh;
    });
    env.forEach(function (mesh) {
      mesh.poly.forEach(function (poly) {
        var fill = shade(poly, ax.d);
        if (fill === null) { return; }
        var points = "", depth = 0;
        poly.forEach(function (p) {
          var q = at(p);
          points += (points === "" ? "" : " ") + fmt(q[0]) + "," + fmt(q[1]);
          depth += q[2];
        });
        items.push({ depth: depth / poly.length, node: el("polygon", {
          "class": "v3d-surface", "data-name": mesh.name, points: points,
          fill: fill, "fill-opacity": String(D.surfaceOpacity) }) });
      });
      mesh.seg.forEach(function (g) {
        var a = at([g[0], g[1], g[2]]), b = at([g[3], g[4], g[5]]);
        items.push({ depth: 0.5 * (a[2] + b[2]), node: el("line", {
          "class": "v3d-env", "data-name": mesh.name,
          x1: fmt(a[0]), y1: fmt(a[1]), x2: fmt(b[0]), y2: fmt(b[1]),
          stroke: "#b4b4b4", "stroke-width": "1" }) });
      });
    });
    var q = state.quantity;
    // Every other result whose toggle is on, as thin dashed lines in its own colour
    // behind the shown result's hoses (the reference in black).
    D.runs.forEach(function (other, k) {
      if (k === state.run || !state.overlay[k]) { return; }
      other.rods.forEach(function (rod) {
        for (var j = 1; j < rod.p.length; j++) {
          var a = at(rod.p[j - 1]), b = at(rod.p[j]);
          items.push({ depth: 0.5 * (a[2] + b[2]) + 1e-6, node: el("line", {
            "class": "v3d-overlay", "data-result": other.label, "data-rod": rod.name,
            x1: fmt(a[0]), y1: fmt(a[1]), x2: fmt(b[0]),
            y2: fmt(b[1]), stroke: D.overlayColours[k % D.overlayColours.length],
            "stroke-opacity": "0.7", "stroke-width": "1.5", "stroke-dasharray": "4 3" }) });
        }
      });
    });
    run.rods.forEach(function (rod) {
      var width = Math.max(2, 2 * rod.r * s);
      for (var j = 1; j < rod.p.length; j++) {
        var a = at(rod.p[j - 1]), b = at(rod.p[j]);
        items.push({ depth: 0.5 * (a[2] + b[2]), node: el("line", {
          "class": "v3d-edge", "data-rod": rod.name, "data-j": String(j),
          x1: fmt(a[0]), y1: fmt(a[1]), x2: fmt(b[0]), y2: fmt(b[1]),
          stroke: colour(edgeT(rod, q, j)), "stroke-width": fmt(width),
          "stroke-linecap": "round" }) });
      }
    });
    run.parts.forEach(function (part) {
      var a = at(part.a), b = at(part.b);
      items.push({ depth: 0.5 * (a[2] + b[2]), node: el("line", {
        "class": "v3d-part", "data-kind": part.kind, "data-name": part.name,
        x1: fmt(a[0]), y1: fmt(a[1]), x2: fmt(b[0]), y2: fmt(b[1]),
        stroke: D.partColours[part.kind] || "#000000",
        "stroke-width": fmt(Math.max(3, part.w * s)), "stroke-linecap": "round" }) });
    });
    // Far first.
    items.sort(function (x, y) { return y.depth - x.depth; });
    while (scene.firstChild) { scene.removeChild(scene.firstChild); }
    items.forEach(function (it) { scene.appendChild(it.node); });
    run.contacts.forEach(function (k) {
      var p = at(k.p);
      var tip = at([k.p[0] + k.n[0], k.p[1] + k.n[1], k.p[2] + k.n[2]]);
      var dx = tip[0] - p[0], dy = tip[1] - p[1], l = Math.sqrt(dx * dx + dy * dy);
      if (l > 1e-9 * s) {
        dx /= l; dy /= l;
        scene.appendChild(el("line", { "class": "v3d-contact-arrow",
          x1: fmt(p[0] - 26 * dx), y1: fmt(p[1] - 26 * dy), x2: fmt(p[0]), y2: fmt(p[1]),
          stroke: D.contactColour, "stroke-width": "2" }));
      }
      scene.appendChild(el("circle", { "class": "v3d-contact", "data-rod": k.rod,
        "data-with": k.with,
        "data-force-n": String(k.f), cx: fmt(p[0]), cy: fmt(p[1]), r: "4",
        fill: D.contactColour, stroke: "#ffffff" }));
    });
    legend();
  }

  function legend() {
    var r = D.ranges[state.quantity];
    var info = D.quantities[state.quantity];
    var top = document.getElementById("v3d-legend-top");
    var bottom = document.getElementById("v3d-legend-bottom");
    var title = document.getElementById("v3d-legend-title");
    var reversed = state.quantity === "rb" || state.quantity === "c";
    if (title) { title.textContent = info.label + " [" + info.unit + "]"; }
    if (top) { top.textContent = (reversed ? r[0] : r[1]).toPrecision(4) + (reversed ? " (tight)" : ""); }
    if (bottom) { bottom.textContent = (reversed ? "≥ " + r[1].toPrecision(4) : r[0].toPrecision(4)); }
  }

  function show(target) {
    if (!readout || !target || !target.getAttribute) { return; }
    var force = target.getAttribute("data-force-n");
    if (force !== null) {
      readout.textContent = "contact of " + target.getAttribute("data-rod") + " with " +
        target.getAttribute("data-with") + ": " + Number(force).toPrecision(4) + " N";
      return;
    }
    var kind = target.getAttribute("data-kind");
    if (kind) {
      readout.textContent = kind + " " + target.getAttribute("data-name");
      return;
    }
    var name = target.getAttribute("data-rod"), j = target.getAttribute("data-j");
    if (!name || j === null) { return; }
    var rod = D.runs[state.run].rods.filter(function (x) { return x.name === name; })[0];
    if (!rod) { return; }
    var i = Number(j);
    function v(k, digits) {
      var x = rod[k] ? rod[k][i] : null;
      return x === null || x === undefined ? "–" : Number(x).toPrecision(digits);
    }
    var clear = rod.c && typeof rod.c[i] === "number" ? Number(rod.c[i]).toPrecision(4) + " mm"
      : (rod.c && rod.c.length > 0 ? "over " + D.clearanceSearch.toPrecision(4) + " mm" : "– (no environment)");
    readout.textContent = name + ": s = " + v("s", 4) + " mm, |f| = " + v("f", 4) +
      " N, |m| = " + v("m", 4) + " N·m, bend radius = " + v("rb", 4) + " mm, clearance = " +
      clear +
      (state.run !== 0 ? ", moved " + v("d", 4) + " mm from the reference" : "");
  }

  var drag = null;
  svg.addEventListener("mousedown", function (ev) {
    drag = { x: ev.clientX, y: ev.clientY, pan: ev.shiftKey };
    ev.preventDefault();
  });
  window.addEventListener("mouseup", function () { drag = null; });
  window.addEventListener("mousemove", function (ev) {
    if (!drag) { return; }
    var dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
    drag.x = ev.clientX; drag.y = ev.clientY;
    if (drag.pan) { state.panX += dx; state.panY += dy; }
    else {
      state.yaw -= 0.5 * dx;
      state.pitch = Math.max(-90, Math.min(90, state.pitch + 0.5 * dy));
    }
    draw();
  });
  svg.addEventListener("wheel", function (ev) {
    state.zoom *= ev.deltaY < 0 ? 1.15 : 1 / 1.15;
    ev.preventDefault();
    draw();
  });
  svg.addEventListener("mouseover", function (ev) { show(ev.target); });

  var quantity = document.getElementById("v3d-quantity");
  if (quantity) {
    quantity.addEventListener("change", function () { state.quantity = quantity.value; draw(); });
  }
  Array.prototype.forEach.call(document.querySelectorAll("input.v3d-toggle"), function (box) {
    box.addEventListener("change", function () {
      state.overlay[Number(box.getAttribute("data-run"))] = box.checked;
      draw();
    });
  });
  var result = document.getElementById("v3d-result");
  if (result) {
    result.addEventListener("change", function () { state.run = Number(result.value); draw(); });
  }
  // A motion: the slider and the play button step through the poses (results).
  var pose = document.getElementById("v3d-pose");
  if (pose && D.poses) {
    var poseLabel = document.getElementById("v3d-pose-label");
    var play = document.getElementById("v3d-play");
    var timer = null;
    var showPose = function (k) {
      state.run = k;
      pose.value = String(k);
      if (result) { result.value = String(k); }
      if (poseLabel) { poseLabel.textContent = D.poses[k]; }
      draw();
    };
    pose.addEventListener("input", function () { showPose(Number(pose.value)); });
    if (result) {
      result.addEventListener("change", function () { pose.value = result.value; showPose(Number(result.value)); });
    }
    if (play) {
      play.addEventListener("click", function () {
        if (timer !== null) { clearInterval(timer); timer = null; play.textContent = "play"; return; }
        play.textContent = "pause";
        timer = setInterval(function () { showPose((state.run + 1) % D.runs.length); }, 200);
      });
    }
  }
  Array.prototype.forEach.call(document.querySelectorAll("button[data-yaw]"), function (b) {
    b.addEventListener("click", function () {
      state.yaw = Number(b.getAttribute("data-yaw"));
      state.pitch = Number(b.getAttribute("data-pitch"));
      state.zoom = 1; state.panX = 0; state.panY = 0;
      draw();
    });
  });
  svg.setAttribute("data-interactive", "true");
  draw();
})();
