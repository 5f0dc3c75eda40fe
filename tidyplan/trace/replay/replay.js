/* The replay page's script (`tidyplan trace FILE --html OUT`, tidyplan/trace_html.py).

   It draws the run's data, which trace_html.py computed from the trace and embedded as JSON,
   against the simulated clock: the room and the robot on an SVG map, the plan and the belief
   beside it, the timeline under it, a replan's diff in a drawer. Vanilla JS and inline SVG:
   nothing is fetched, so the page works offline in any current browser.

   The URL's hash drives it too: #t=S opens at S simulated seconds, #replan=N opens replan N's
   diff; #selftest=S1,S2,...&replan=N&play=SPEED (tests/test_trace_html.py, in headless
   Chromium) moves the slider to each time, reads back where the robot is drawn, opens the
   diff, plays for a second, and writes what it found as JSON into <pre id="selftest">. */
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("data").textContent);
  const NS = "http://www.w3.org/2000/svg"; // the SVG namespace: a name, nothing is fetched
  const $ = (id) => document.getElementById(id);
  const S = 100; // map units per metre
  const PAD = 0.35; // metres around the room
  const END = Math.max(D.t_end, 0.1);
  const KEYS = D.track;
  const KEY_T = KEYS.map((k) => k[0]);
  const PLANS = D.plans;
  const PLAN_T = PLANS.map((p) => p.sim_s);
  const TL = D.timeline;
  const LOOK_ROW = TL.units.indexOf("look");
  const LOOKS = TL.runs.filter((r) => r[0] === LOOK_ROW);
  const FIRST_LOOK = D.replans.length ? D.replans[0].sim_s : 0; // the look at the start, before the first plan
  if (FIRST_LOOK > 0 && !(TL.actions.length && TL.actions[0][0] < FIRST_LOOK)) LOOKS.unshift([LOOK_ROW, 0, FIRST_LOOK, true]);
  const SPEEDS = [1, 2, 5, 10, 20, 50, 100, 200];
  const PAN = [1.75, -3.84]; // the head's pan range in a sweep (rad), tidyplan/exec/bullet_look.py
  let T = 0;
  let playing = false;
  let lastFrame = null;
  let timer = null;
  let sideKey = "";

  // ------------------------------------------------------------------ helpers
  function svg(name, attrs, parent, text) {
    const e = document.createElementNS(NS, name);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }
  function html(tag, attrs, parent, text) {
    const e = document.createElement(tag);
    for (const k in attrs || {}) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }
  function num(x, d) {
    return x === null || x === undefined ? "-" : Number(x).toFixed(d);
  }
  function p3(x) {
    return x === null || x === undefined ? "-" : Number(x).toPrecision(3).replace(/\.?0+$/, "");
  }
  /** the last index i with arr[i] <= t, -1 if none */
  function lastAt(arr, t) {
    let lo = 0;
    let hi = arr.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (arr[mid] <= t) lo = mid + 1;
      else hi = mid;
    }
    return lo - 1;
  }
  function causeText(c) {
    return c === "initial" ? "initial" : c + " (" + (D.causes[c] || "?") + ")";
  }
  function catColour(c) {
    return D.colours.category[c] || "#999999";
  }
  function categoryOf(name) {
    const m = /^unseen-(.+)-\d+$/.exec(name);
    return m ? m[1] : name.replace(/-\d+$/, "");
  }

  /** (x, y, heading) at t: trace_html.pose_at, keyframes joined by straight lines */
  function poseAt(t) {
    if (!KEYS.length) return null;
    const i = lastAt(KEY_T, t);
    if (i < 0) return KEYS[0].slice(1, 4);
    if (i >= KEYS.length - 1) return KEYS[KEYS.length - 1].slice(1, 4);
    const a = KEYS[i];
    const b = KEYS[i + 1];
    const f = b[0] <= a[0] ? 0 : (t - a[0]) / (b[0] - a[0]);
    return [a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2]), b[3]];
  }

  // ------------------------------------------------------------------ the map's frame
  const frame = (function () {
    if (D.room) return D.room.bounds.slice();
    const xs = KEYS.map((k) => k[1]);
    const ys = KEYS.map((k) => k[2]);
    for (const n in D.waypoints) {
      xs.push(D.waypoints[n][0]);
      ys.push(D.waypoints[n][1]);
    }
    if (!xs.length) return [0, 1, 0, 1];
    return [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
  })();
  const X = (x) => (x - frame[0] + PAD) * S;
  const Y = (y) => (frame[3] + PAD - y) * S;
  const toWorld = (u, v) => [u / S + frame[0] - PAD, frame[3] + PAD - v / S];
  const map = $("map");
  const LEGEND_W = 2.3; // metres of the map's width kept right of the room for the legend
  map.setAttribute("viewBox", "0 0 " + (frame[1] - frame[0] + 2 * PAD + LEGEND_W) * S + " " + (frame[3] - frame[2] + 2 * PAD) * S);
  const layer = {};
  for (const name of ["room", "truth", "path", "looks", "cone", "virtual", "belief", "robot", "legend"]) {
    layer[name] = svg("g", { id: "layer-" + name }, map);
  }

  function drawRoom() {
    const g = layer.room;
    const r = D.room;
    if (!r) {
      svg("text", { x: 8, y: 18, "font-size": 13, fill: "#9a6700" }, g, "the room is not drawn (see the note above)");
      return;
    }
    const [x0, x1, y0, y1] = r.bounds;
    svg("rect", { x: X(x0), y: Y(y1), width: (x1 - x0) * S, height: (y1 - y0) * S, fill: "#fdfdfd", stroke: "#222", "stroke-width": 5 }, g);
    for (const [name, cx, cy, sx, sy, kind] of r.furniture) {
      const f = svg("rect", { x: X(cx - sx / 2), y: Y(cy + sy / 2), width: sx * S, height: sy * S, fill: "#e4e4e4", stroke: "#999" }, g);
      svg("title", {}, f, name + " (" + kind + ")");
      svg("text", { x: X(cx), y: Y(cy) + 3, "font-size": 9, fill: "#666", "text-anchor": "middle" }, g, name);
    }
    for (const [name, category, x, y] of r.deposits) {
      const d = svg("rect", { x: X(x) - 9, y: Y(y) - 9, width: 18, height: 18, fill: catColour(category), stroke: "#000", "stroke-width": 1.5 }, g);
      svg("title", {}, d, "deposit " + name + " for " + category);
      svg("text", { x: X(x) - 11, y: Y(y) - 11, "font-size": 9, "text-anchor": "start" }, g, name + " (" + category + ")");
    }
    const views = r.viewpoints.map((v) => v.slice());
    for (const n in D.waypoints) {
      const w = D.waypoints[n];
      if (w[2] === "viewpoint" && !views.some((v) => v[0] === n)) views.push([n, w[0], w[1]]);
    }
    for (const [name, x, y] of views) {
      svg("path", { d: "M" + X(x) + " " + (Y(y) - 7) + "l7 7l-7 7l-7 -7z", fill: "none", stroke: "#777", "stroke-width": 1.5 }, g);
      svg("text", { x: X(x) + 9, y: Y(y) + 12, "font-size": 9, fill: "#777" }, g, name);
    }
    const [ex, ey] = r.entrance;
    svg("text", { x: X(ex), y: Y(ey) + 30, "font-size": 9, fill: "#777", "text-anchor": "middle" }, g, "entrance");
  }

  function drawTruth() {
    const g = layer.truth;
    if (!D.room) return;
    for (const [name, category, x, y] of D.room.items) {
      const c = svg("circle", { cx: X(x), cy: Y(y), r: 7, fill: "none", stroke: catColour(category), "stroke-width": 2.5 }, g);
      svg("title", {}, c, name + " (" + category + "): where it really was at the start (the scenario)");
      const end = D.end_items[name];
      if (!end || String(end[0]).startsWith("tidied") || end[1] === null) continue;
      const [, ex, ey] = end;
      if (Math.hypot(ex - x, ey - y) > 0.05) {
        svg("line", { x1: X(x), y1: Y(y), x2: X(ex), y2: Y(ey), stroke: "#888", "stroke-dasharray": "4 3" }, g);
      }
      const e = svg("circle", { cx: X(ex), cy: Y(ey), r: 5, fill: catColour(category), stroke: "#666", "stroke-width": 1.5 }, g);
      svg("title", {}, e, name + ": where it really was at the end (" + end[0] + ", the trace's end event)");
    }
  }

  function drawLegend() {
    const g = layer.legend;
    const rows = [
      ["ring", "true place at the start (scenario)"],
      ["dot", "true place at the end, untidied (end event)"],
      ["diamond", "item as the belief holds it"],
      ["ghost", "virtual object the plan assumes"],
      ["eye", "where the robot looked"],
    ];
    const x0 = X(frame[1]) + PAD * S * 0.6;
    let y = Y(frame[3]) + 6;
    for (const [kind, text] of rows) {
      if (kind === "ring") svg("circle", { cx: x0 + 6, cy: y, r: 5, fill: "none", stroke: "#555", "stroke-width": 2 }, g);
      if (kind === "dot") svg("circle", { cx: x0 + 6, cy: y, r: 4, fill: "#555", stroke: "#666" }, g);
      if (kind === "diamond") svg("path", { d: diamond(x0 + 6, y, 5), fill: "#555", stroke: "#000" }, g);
      if (kind === "ghost") svg("path", { d: diamond(x0 + 6, y, 5), fill: "none", stroke: "#555", "stroke-dasharray": "2 2" }, g);
      if (kind === "eye") svg("circle", { cx: x0 + 6, cy: y, r: 2.5, fill: "#444", opacity: 0.6 }, g);
      svg("text", { x: x0 + 16, y: y + 3, "font-size": 9, fill: "#444" }, g, text);
      y += 13;
    }
  }

  function diamond(x, y, r) {
    return "M" + x + " " + (y - r) + "l" + r + " " + r + "l" + -r + " " + r + "l" + -r + " " + -r + "z";
  }

  // the robot: its camera cone under it, its body and heading; the body is what tests read back
  if (D.room) {
    const [x0, x1, y0, y1] = D.room.bounds;
    const clip = svg("clipPath", { id: "in-room" }, svg("defs", {}, map));
    svg("rect", { x: X(x0), y: Y(y1), width: (x1 - x0) * S, height: (y1 - y0) * S }, clip);
    layer.cone.setAttribute("clip-path", "url(#in-room)"); // a reference inside the page
  }
  const cone = svg("path", { fill: "#f2c200", "fill-opacity": 0.18, stroke: "#d9a800", "stroke-opacity": 0.5 }, layer.cone);
  const robot = svg("g", { id: "robot" }, layer.robot);
  const radius = (D.room ? D.room.robot_radius : 0.22) * S;
  svg("circle", { id: "robot-body", cx: 0, cy: 0, r: radius, fill: "#3a3a3a", "fill-opacity": 0.82, stroke: "#000", "stroke-width": 1.5 }, robot);
  svg("path", { d: "M" + (radius + 9) + " 0L" + (radius - 6) + " -9L" + (radius - 6) + " 9z", fill: "#ff5a00", stroke: "#000" }, robot);
  // the whole recorded path, faint; the part driven by t over it, coloured by plan
  svg("polyline", { points: KEYS.map((k) => X(k[1]) + "," + Y(k[2])).join(" "), fill: "none", stroke: "#bbb", "stroke-width": 1.2, "stroke-dasharray": "5 4" }, layer.path);
  const preLine = svg("polyline", { fill: "none", stroke: "#777", "stroke-width": 3 }, layer.path);
  const pathLines = PLANS.map((p, i) => svg("polyline", { fill: "none", stroke: D.colours.plan[i % D.colours.plan.length], "stroke-width": 3, "stroke-linejoin": "round", opacity: 0.85 }, layer.path));

  function lookAt(t) {
    for (const r of LOOKS) if (r[1] <= t && t < r[2]) return (t - r[1]) / Math.max(r[2] - r[1], 1e-6);
    return null;
  }

  function drawRobot(t) {
    const pose = poseAt(t);
    if (!pose) return;
    const [x, y, h] = pose;
    robot.setAttribute("transform", "translate(" + X(x) + "," + Y(y) + ") rotate(" + -h + ")");
    robot.dataset.x = x;
    robot.dataset.y = y;
    robot.dataset.heading = h;
    const sweep = lookAt(t);
    let dir = (h * Math.PI) / 180;
    if (sweep !== null) dir += PAN[0] + sweep * (PAN[1] - PAN[0]);
    const half = ((D.camera.fov / 2) * Math.PI) / 180;
    const [r0, r1] = [D.camera.near * S, D.camera.range * S];
    const pt = (r, a) => X(x) + r * Math.cos(a) + " " + (Y(y) - r * Math.sin(a));
    cone.setAttribute("d", "M" + pt(r0, dir - half) + "L" + pt(r1, dir - half) + "A" + r1 + " " + r1 + " 0 0 0 " + pt(r1, dir + half) + "L" + pt(r0, dir + half) + "A" + r0 + " " + r0 + " 0 0 1 " + pt(r0, dir - half) + "z");
  }

  function drawPath(t) {
    const upto = (a, b) => {
      const pts = [];
      const i0 = Math.max(lastAt(KEY_T, a), 0);
      const first = poseAt(a);
      if (first) pts.push(first);
      for (let i = i0 + 1; i < KEYS.length && KEYS[i][0] <= b; i++) pts.push(KEYS[i].slice(1, 3));
      const last = poseAt(b);
      if (last) pts.push(last);
      return pts.map((p) => X(p[0]) + "," + Y(p[1])).join(" ");
    };
    const firstPlan = PLANS.length ? PLANS[0].sim_s : END;
    preLine.setAttribute("points", upto(0, Math.min(t, firstPlan)));
    PLANS.forEach((p, i) => {
      const until = i + 1 < PLANS.length ? PLANS[i + 1].sim_s : END;
      pathLines[i].setAttribute("points", t < p.sim_s ? "" : upto(p.sim_s, Math.min(t, until)));
    });
    layer.looks.textContent = "";
    for (const r of LOOKS) {
      if (r[2] > t) break;
      const p = poseAt(r[2]);
      if (p) svg("circle", { cx: X(p[0]), cy: Y(p[1]), r: 2.5, fill: "#444", opacity: 0.55 }, layer.looks);
    }
  }

  // ------------------------------------------------------------------ belief and plan at t
  function beliefAt(t) {
    const out = [];
    for (const name in D.belief) {
      const b = D.belief[name];
      const ks = b.keys;
      let k = null;
      for (const key of ks) {
        if (key[0] > t) break;
        k = key;
      }
      if (k) out.push({ name: name, category: b.category, state: k[1], x: k[2], y: k[3], since: k[0] });
    }
    return out;
  }

  function planAt(t) {
    const i = lastAt(PLAN_T, t);
    return i < 0 ? null : { index: i, plan: PLANS[i] };
  }

  function renamed(step, plan, t) {
    const names = {};
    for (const [bt, v, item] of plan.binds) if (bt <= t) names[v] = item;
    return step.replace(/[^\s()]+/g, (w) => names[w] || w);
  }

  function assumptionState(step, i, plan, t) {
    if (plan.passed[i] === null || plan.passed[i] > t) return "ahead";
    const text = renamed(step, plan, t);
    for (const [at, action, holds] of D.assumptions) {
      if (at >= plan.sim_s && at <= t && action === text) return holds ? "confirmed" : "contradicted";
    }
    return "set aside, to be checked";
  }

  function actionAt(t) {
    for (const a of TL.actions) if (a[0] <= t && t <= a[1]) return a;
    return null;
  }

  function drawBelief(t, items, current) {
    layer.belief.textContent = "";
    layer.virtual.textContent = "";
    const pose = poseAt(t);
    const stack = {};
    for (const it of items) {
      let x = it.x;
      let y = it.y;
      if (it.state === "held" && pose) [x, y] = pose;
      else if (it.state === "tidied" && x !== null) {
        const n = (stack[x + "," + y] = (stack[x + "," + y] || 0) + 1);
        x += 0.12 + 0.09 * (n - 1);
      } else if (it.state !== "placed" || x === null) continue;
      const d = svg("path", { d: diamond(X(x), Y(y), 7), fill: catColour(it.category), stroke: "#000", "stroke-width": 1.3 }, layer.belief);
      svg("title", {}, d, it.name + ": believed " + it.state + " (since " + num(it.since, 1) + " s)");
      if (it.state !== "tidied") svg("text", { x: X(x) + 8, y: Y(y) - 6, "font-size": 9, fill: "#111" }, layer.belief, it.name + (it.state === "held" ? " (held)" : ""));
    }
    if (!current || (current.plan.until !== null && current.plan.until <= t)) return;
    const plan = current.plan;
    const spots = {};
    plan.steps.forEach((step, i) => {
      const m = /^\(assume-item-near (\S+) (\S+)\)$/.exec(renamed(step, plan, t));
      if (!m || !m[1].startsWith("unseen-") || assumptionState(step, i, plan, t) === "contradicted") return;
      const w = D.waypoints[m[2]];
      if (!w) return;
      const k = (spots[m[2]] = (spots[m[2]] || 0) + 1) - 1; // stacked under the waypoint, one a row
      const [vx, vy] = [X(w[0]) - 14, Y(w[1]) + 16 + 15 * k];
      const g = svg("path", { d: diamond(vx, vy, 7), fill: "none", stroke: catColour(categoryOf(m[1])), "stroke-width": 2, "stroke-dasharray": "3 2" }, layer.virtual);
      svg("title", {}, g, "virtual object " + m[1] + ", assumed near " + m[2]);
      svg("text", { x: vx + 9, y: vy + 3, "font-size": 9, fill: "#555" }, layer.virtual, m[1]);
    });
  }

  const nowClock = html("div", {}, $("now"));
  const nowAction = html("div", {}, $("now"));

  function renderSide(t, items, current) {
    const action = actionAt(t);
    const pose = poseAt(t);
    const unit = TL.runs.find((r) => r[1] <= t && t <= r[2] && r[0] !== LOOK_ROW) || TL.runs.find((r) => r[1] <= t && t <= r[2]);
    const key = [current ? current.index : -1, current ? current.plan.passed.filter((p) => p !== null && p <= t).length : 0,
      action ? action[0] : -1, unit ? unit[0] + ":" + unit[1] : "", items.map((i) => i.state + i.since).join()].join("|");
    nowClock.textContent = "t = " + num(t, 1) + " s · robot at " + (pose ? "(" + num(pose[0], 2) + ", " + num(pose[1], 2) + "), heading " + num(pose[2], 0) + "°" : "?");
    if (key === sideKey) return;
    sideKey = key;
    nowAction.textContent = action ? "action: " + action[2] + (action[5] ? " (the loop's own: " + action[5] + ")" : "") + (action[3] ? "" : " — failed") : "no action running";
    nowAction.textContent += unit ? " · unit: " + TL.units[unit[0]] + (unit[3] ? "" : " (this run fails)") : "";
    renderPlan(t, current);
    renderBelief(t, items);
  }

  function renderPlan(t, current) {
    const panel = $("plan");
    panel.textContent = "";
    if (!current) {
      html("h2", {}, panel, "Plan: none yet");
      return;
    }
    const p = current.plan;
    const done = p.passed.filter((x) => x !== null && x <= t).length;
    html("h2", {}, panel, "Plan of replan " + p.replan + ": P" + (p.stratum || "-") + " · cost " + num(p.cost, 1) + " · p " + p3(p.probability) + " · " + done + " of " + p.steps.length + " steps passed");
    html("div", {}, panel, causeText(p.cause) + (p.why ? ": " + p.why : "") + " · goal " + p.goal_kind + " " + p.goal);
    if (p.until !== null && p.until <= t) html("div", { class: "warn" }, panel, "dropped at " + num(p.until, 1) + " s: the loop is replanning");
    const ol = html("ol", {}, panel);
    let now = null;
    p.steps.forEach((step, i) => {
      const passed = p.passed[i] !== null && p.passed[i] <= t;
      const running = !passed && p.began[i] !== null && p.began[i] <= t;
      const li = html("li", { class: (passed ? "done" : running ? "now" : "rest") + (step.startsWith("(assume") ? " assume" : "") }, ol, renamed(step, p, t));
      if (running || (!now && !passed)) now = now || li;
    });
    if (now) ol.scrollTop = Math.max(now.offsetTop - ol.offsetTop - 40, 0);
    const rests = p.steps.map((s, i) => [s, i]).filter(([s]) => s.startsWith("(assume"));
    html("h2", {}, panel, "Assumptions the plan rests on: " + rests.length);
    const tbl = html("table", {}, panel);
    for (const [s, i] of rests) {
      const tr = html("tr", {}, tbl);
      html("td", {}, tr, renamed(s, p, t));
      const st = assumptionState(s, i, p, t);
      html("td", { class: st === "confirmed" ? "ok" : st === "contradicted" ? "bad" : "" }, tr, st);
    }
  }

  function renderBelief(t, items) {
    const panel = $("belief");
    panel.textContent = "";
    const seen = new Set();
    for (const o of D.observe) if (o[0] <= t) for (const n of o[1]) seen.add(n);
    const looks = LOOKS.filter((r) => r[2] <= t).length;
    html("h2", {}, panel, "Belief at " + num(t, 1) + " s: " + items.filter((i) => i.state !== "gone").length + " items · seen so far " + seen.size + " · " + looks + (looks === 1 ? " look" : " looks"));
    const tbl = html("table", {}, panel);
    const order = { held: 0, placed: 1, seen: 2, tidied: 3, gone: 4 };
    const words = { held: "in the hand", placed: "placed at", seen: "seen, place not recorded", tidied: "tidied", gone: "forgotten" };
    for (const it of items.slice().sort((a, b) => order[a.state] - order[b.state] || a.name.localeCompare(b.name))) {
      const tr = html("tr", {}, tbl);
      const td = html("td", {}, tr);
      html("span", { class: "swatch", style: "background:" + catColour(it.category) }, td);
      td.appendChild(document.createTextNode(it.name));
      html("td", {}, tr, words[it.state] + (it.state === "placed" && it.x !== null ? " (" + num(it.x, 2) + ", " + num(it.y, 2) + ")" : "") + " since " + num(it.since, 1) + " s");
    }
  }

  // ------------------------------------------------------------------ the timeline
  const TW = 1360;
  const TLEFT = 112;
  const TRIGHT = 14;
  const ROWH = 15;
  const rows = ["replans", "plan", "action", ...TL.units];
  const rowY = (i) => 6 + (i === 0 ? 0 : 24 + (i - 1) * ROWH);
  const tx = (t) => TLEFT + ((TW - TLEFT - TRIGHT) * t) / END;
  const timeline = $("timeline");
  const TH = rowY(rows.length) + 34;
  timeline.setAttribute("viewBox", "0 0 " + TW + " " + TH);
  let cursor = null;

  function drawTimeline() {
    const g = svg("g", {}, timeline);
    rows.forEach((name, i) => {
      svg("text", { x: TLEFT - 6, y: rowY(i) + (i === 0 ? 14 : 11), "font-size": 10, "text-anchor": "end", fill: "#333" }, g, name);
      if (i > 0) svg("line", { x1: TLEFT, x2: TW - TRIGHT, y1: rowY(i) + ROWH - 1, y2: rowY(i) + ROWH - 1, stroke: "#eee" }, g);
    });
    PLANS.forEach((p, i) => {
      const until = i + 1 < PLANS.length ? PLANS[i + 1].sim_s : END;
      const r = svg("rect", { x: tx(p.sim_s), y: rowY(1) + 1, width: Math.max(tx(until) - tx(p.sim_s), 1), height: ROWH - 3, fill: D.colours.plan[i % D.colours.plan.length] }, g);
      svg("title", {}, r, "plan of replan " + p.replan + ": P" + p.stratum + ", cost " + num(p.cost, 1) + ", p " + p3(p.probability));
      if (tx(until) - tx(p.sim_s) > 14) svg("text", { x: (tx(p.sim_s) + tx(until)) / 2, y: rowY(1) + 10, "font-size": 9, fill: "#fff", "text-anchor": "middle" }, g, p.replan);
    });
    for (const [a, b, text, ok, last, purpose] of TL.actions) {
      const r = svg("rect", { x: tx(a), y: rowY(2) + 1, width: Math.max(tx(b) - tx(a), 1), height: ROWH - 3, fill: D.colours.action[last] || "#ccc", stroke: ok ? "#fff" : "#c00000", "stroke-width": ok ? 0.5 : 1.5 }, g);
      svg("title", {}, r, text + (purpose ? " (" + purpose + ")" : "") + (ok ? "" : ": failed") + ", " + num(a, 1) + "–" + num(b, 1) + " s");
    }
    for (const [row, a, b, ok] of TL.runs) {
      const r = svg("rect", { x: tx(a), y: rowY(3 + row) + 2, width: Math.max(tx(b) - tx(a), 1), height: ROWH - 5, fill: "#c6dbef", stroke: ok ? "#666" : "#c00000", "stroke-width": ok ? 0.4 : 1.5 }, g);
      svg("title", {}, r, TL.units[row] + (ok ? "" : " (failed)") + ", " + num(a, 1) + "–" + num(b, 1) + " s");
    }
    for (const [t, unit, failure, klass, layerName, then] of TL.recoveries) {
      const row = TL.units.indexOf(unit);
      const [x, y] = [tx(t), rowY(3 + Math.max(row, 0)) + ROWH / 2 - 1];
      const m = svg("path", { d: "M" + (x - 4) + " " + (y - 4) + "l8 8m0 -8l-8 8", stroke: D.colours.class[klass] || "#000", "stroke-width": 2.2 }, g);
      svg("title", {}, m, "recovery at " + num(t, 1) + " s: " + unit + " " + failure + " (class " + klass + ") → " + layerName + (then ? ": " + then.join(", ") : ""));
    }
    drawReplans(g);
    drawAxis(g);
    cursor = svg("line", { y1: 2, y2: rowY(rows.length), stroke: "#e00", "stroke-width": 1.5 }, timeline);
  }

  // a marker per replan, coloured by cause; markers closer than 13 px are set side by side, each
  // joined to its time by a thin line, so that every one can be clicked
  function drawReplans(g) {
    let shown = -99;
    for (const r of D.replans) {
      const x = tx(r.sim_s);
      const colour = D.colours.cause[r.cause] || "#000";
      if (r.replan > 0) svg("line", { x1: x, x2: x, y1: rowY(1), y2: rowY(rows.length), stroke: colour, "stroke-dasharray": "3 3", opacity: 0.6 }, g);
      shown = Math.max(x, shown + 13);
      const m = svg("g", { class: "replan", "data-replan": r.replan }, g);
      if (shown > x + 0.5) svg("line", { x1: shown, x2: x, y1: rowY(0) + 18, y2: rowY(1), stroke: colour }, m);
      svg("polygon", { points: shown - 6 + "," + (rowY(0) + 8) + " " + (shown + 6) + "," + (rowY(0) + 8) + " " + shown + "," + (rowY(0) + 19), fill: colour, stroke: "#000" }, m);
      svg("text", { x: shown, y: rowY(0) + 6, "font-size": 9, "text-anchor": "middle" }, m, r.replan);
      svg("title", {}, m, "replan " + r.replan + " at " + num(r.sim_s, 1) + " s: " + causeText(r.cause) + (r.why ? ": " + r.why : "") + " — click for its diff");
      m.addEventListener("click", (ev) => {
        ev.stopPropagation();
        setTime(r.sim_s);
        openDiff(r.replan);
      });
    }
  }

  function drawAxis(g) {
    const y = rowY(rows.length) + 2;
    const step = [10, 20, 50, 100, 200, 500, 1000, 2000, 5000].find((s) => END / s <= 14) || 10000;
    svg("line", { x1: TLEFT, x2: TW - TRIGHT, y1: y, y2: y, stroke: "#444" }, g);
    for (let t = 0; t <= END; t += step) {
      svg("line", { x1: tx(t), x2: tx(t), y1: y, y2: y + 4, stroke: "#444" }, g);
      svg("text", { x: tx(t), y: y + 14, "font-size": 9, "text-anchor": "middle" }, g, t + " s");
    }
    let lx = TLEFT;
    const ly = y + 27;
    for (const k in D.colours.class) {
      svg("path", { d: "M" + lx + " " + (ly - 7) + "l7 7m0 -7l-7 7", stroke: D.colours.class[k], "stroke-width": 2 }, g);
      svg("text", { x: lx + 10, y: ly, "font-size": 9 }, g, "recovery, class " + k);
      lx += 110;
    }
    for (const c in D.colours.cause) {
      svg("polygon", { points: lx + "," + (ly - 8) + " " + (lx + 10) + "," + (ly - 8) + " " + (lx + 5) + "," + ly, fill: D.colours.cause[c], stroke: "#000" }, g);
      svg("text", { x: lx + 13, y: ly, "font-size": 9 }, g, "(" + D.causes[c] + ") " + c);
      lx += 40 + 5.2 * c.length;
    }
  }

  function timeFromEvent(ev) {
    const p = new DOMPoint(ev.clientX, ev.clientY).matrixTransform(timeline.getScreenCTM().inverse());
    return Math.min(Math.max(((p.x - TLEFT) / (TW - TLEFT - TRIGHT)) * END, 0), END);
  }

  // ------------------------------------------------------------------ a replan's diff
  function openDiff(n) {
    const d = D.replans.find((r) => r.replan === n);
    if (!d) return;
    const body = $("diff-body");
    body.textContent = "";
    html("h2", {}, body, "replan " + d.replan + " at " + d.sim_s + " s simulated: " + causeText(d.cause) + (d.why ? ": " + d.why : ""));
    for (const a of d.attempts) {
      html("pre", {}, body, "  goal " + a.goal_kind + ": " + a.status + ", " + (a.stratum ? "P" + a.stratum + ", " : "") + a.steps + " steps, cost " + num(a.cost, 2) + ", p " + p3(a.probability) + ", " + num(a.planning_time_s, 2) + " s" + (a.message ? " (" + a.message + ")" : ""));
    }
    html("pre", {}, body, "problem: " + (d.problem || "-") + (d.adopted ? "" : " (plan not adopted)"));
    if (d.previous === null) {
      html("pre", {}, body, d.facts_note + "; its plan:");
    } else {
      const ex = d.executed;
      html("pre", {}, body, "executed since replan " + d.previous.replan + ": " + ex.length + " action" + (ex.length === 1 ? "" : "s") + (ex.length <= 4 ? ": " + ex.join(" ") : ", the last " + ex[ex.length - 1]));
      html("pre", { id: "diff-counts" }, body, "plan against the rest of replan " + d.previous.replan + " (" + d.rest + " steps left): " + d.kept + " kept, " + d.dropped + " dropped, " + d.added + " added");
    }
    steps(body, d.diff);
    if (d.previous !== null) facts(body, d);
    const panel = $("diff");
    panel.hidden = false;
    panel.dataset.replan = n;
    panel.scrollTop = 0;
  }

  function steps(body, lines) {
    const pre = html("pre", { id: "diff-steps" }, body);
    let i = 0;
    while (i < lines.length) {
      let j = i;
      while (j < lines.length && lines[j][0] === " ") j++;
      let run = j > i ? lines.slice(i, j) : [lines[i]];
      if (j - i > 5) run = [...run.slice(0, 2), ["", "… " + (j - i - 4) + " kept steps …"], ...run.slice(-2)];
      for (const [mark, step] of run) html("span", { class: mark === "+" ? "add" : mark === "-" ? "del" : mark === "" ? "gap" : "" }, pre, "  " + mark + " " + step + "\n");
      i = j > i ? j : i + 1;
    }
  }

  function facts(body, d) {
    const f = d.facts;
    if (!f) {
      html("pre", {}, body, d.facts_note);
      return;
    }
    let added = f.added.length;
    let removed = f.removed.length;
    let values = f.values.length;
    for (const k in f.counted) {
      added += f.counted[k][0];
      removed += f.counted[k][1];
      values += f.counted[k][2];
    }
    html("pre", {}, body, "belief (" + f.from + " → " + f.to + "): " + added + " facts added, " + removed + " removed, " + values + " values changed");
    const pre = html("pre", {}, body);
    for (const x of f.removed) html("span", { class: "del" }, pre, "  - " + x + "\n");
    for (const x of f.added) html("span", { class: "add" }, pre, "  + " + x + "\n");
    for (const k in f.counted) html("span", {}, pre, "  " + k + ": " + f.counted[k][0] + " added, " + f.counted[k][1] + " removed, " + f.counted[k][2] + " values changed\n");
    for (const [term, a, b] of f.values) html("span", {}, pre, "  " + term + ": " + (a === null ? "-" : a) + " → " + (b === null ? "-" : b) + "\n");
  }

  // ------------------------------------------------------------------ the header
  function renderHeader() {
    const s = D.summary;
    $("title").textContent = D.title;
    for (const n of D.notes) html("div", { class: "note" }, $("notes"), n);
    if (!s.complete) html("div", { class: "note" }, $("notes"), "unfinished: " + s.ended);
    const figs = $("summary");
    const fig = (label, value, cls) => {
      const e = html("span", { class: "fig" }, figs);
      html("b", {}, e, label + " ");
      html("span", { class: cls || "" }, e, value);
    };
    const causes = Object.entries(s.replan_causes).map(([c, n]) => "(" + (D.causes[c] || "?") + ") " + c + " " + n).join(", ") || "none";
    const pairs = (o) => Object.entries(o).map(([k, v]) => k + " " + v).join(", ") || "none";
    fig("ended", (s.success ? "success: " : s.complete ? "FAILED: " : "unfinished: ") + s.ended, s.success ? "ok" : "bad");
    fig("tidied", s.delivered + "/" + s.objects + (s.lost_objects === null ? "" : ", " + s.lost_objects + " lost"));
    fig("replans", s.replans + " (" + causes + "), " + s.replans_avoided + " avoided");
    fig("actions", s.actions + " (" + s.failed_actions + " failed" + (s.paper_actions === null ? "" : ", " + s.paper_actions + " as Yan et al. count") + ")");
    fig("deliveries", pairs(s.strata));
    fig("recoveries", s.recoveries + " (class " + pairs(s.recovery_steps.by_class) + "; exhausted " + s.recovery_steps.exhausted + ")");
    fig("assumptions", s.assumptions.made + " made, " + s.assumptions.confirmed + " confirmed, " + s.assumptions.contradicted + " contradicted");
    fig("WRS score", s.wrs_score + " within " + s.time_limit_s + " s (" + s.wrs_score_at_end + " at the end)");
    fig("distance", num(s.distance_m, 2) + " m");
    fig("time", num(s.sim_time_s, 1) + " s simulated, " + num(s.wall_time_s, 2) + " s wall");
    fig("planning", "median " + num(s.replan_time_s.median, 2) + " s, max " + num(s.replan_time_s.max, 2) + " s");
    const det = html("details", {}, figs);
    html("summary", {}, det, "all the figures (tidyplan trace --json)");
    html("pre", {}, det, JSON.stringify(s, null, 1));
  }

  // ------------------------------------------------------------------ time and controls
  const slider = $("slider");
  const speed = $("speed");
  slider.max = END;
  for (const v of SPEEDS) html("option", { value: v }, speed, v + "×");
  speed.value = 20;

  function setTime(t) {
    T = Math.min(Math.max(Number(t) || 0, 0), END);
    slider.value = T;
    draw();
  }

  function draw() {
    const t = T;
    $("clock").textContent = num(t, 1) + " / " + num(END, 1) + " s";
    drawPath(t);
    drawRobot(t);
    const items = beliefAt(t);
    const current = planAt(t);
    drawBelief(t, items, current);
    renderSide(t, items, current);
    if (cursor) {
      cursor.setAttribute("x1", tx(t));
      cursor.setAttribute("x2", tx(t));
    }
  }

  // a timer, not requestAnimationFrame: it also runs where frames are not drawn (a headless test)
  function play(on) {
    playing = on;
    $("play").textContent = on ? "❚❚ pause" : "▶ play";
    clearTimeout(timer);
    if (on && T >= END) setTime(0);
    lastFrame = null;
    if (on) tick();
  }

  function tick() {
    if (!playing) return;
    const now = performance.now();
    if (lastFrame !== null) setTime(T + ((now - lastFrame) / 1000) * Number(speed.value));
    lastFrame = now;
    if (T >= END) play(false);
    else timer = setTimeout(tick, 40);
  }

  function stepReplan(dir) {
    const ts = D.replans.map((r) => r.sim_s);
    const next = dir > 0 ? ts.find((x) => x > T + 1e-6) : ts.filter((x) => x < T - 1e-6).pop();
    setTime(next === undefined ? (dir > 0 ? END : 0) : next);
  }

  function bind() {
    slider.addEventListener("input", () => setTime(slider.value));
    $("play").addEventListener("click", () => play(!playing));
    $("diff-close").addEventListener("click", () => ($("diff").hidden = true));
    let dragging = false;
    timeline.addEventListener("pointerdown", (ev) => {
      dragging = true;
      setTime(timeFromEvent(ev));
    });
    timeline.addEventListener("pointermove", (ev) => dragging && setTime(timeFromEvent(ev)));
    window.addEventListener("pointerup", () => (dragging = false));
    document.addEventListener("keydown", (ev) => {
      if (ev.target === speed || (ev.key === " " && ev.target.tagName === "BUTTON")) return;
      const i = SPEEDS.indexOf(Number(speed.value));
      const act = {
        " ": () => play(!playing),
        ArrowLeft: () => (ev.shiftKey ? stepReplan(-1) : setTime(T - 5)),
        ArrowRight: () => (ev.shiftKey ? stepReplan(1) : setTime(T + 5)),
        ArrowUp: () => (speed.value = SPEEDS[Math.min(i + 1, SPEEDS.length - 1)]),
        ArrowDown: () => (speed.value = SPEEDS[Math.max(i - 1, 0)]),
        Home: () => setTime(0),
        End: () => setTime(END),
        Escape: () => ($("diff").hidden = true),
      }[ev.key];
      if (act) {
        ev.preventDefault();
        act();
      }
    });
  }

  // ------------------------------------------------------------------ the self-test (tests/test_trace_html.py)
  function selftest(params) {
    const out = { poses: [], diff: null, notes: [], errors: [] };
    try {
      for (const t of params.get("selftest").split(",").filter(Boolean).map(Number)) {
        slider.value = t; // as a user would: move the slider, the page follows its input event
        slider.dispatchEvent(new Event("input", { bubbles: true }));
        const r = $("robot-body").getBoundingClientRect();
        const p = new DOMPoint(r.x + r.width / 2, r.y + r.height / 2).matrixTransform(map.getScreenCTM().inverse());
        const [x, y] = toWorld(p.x, p.y);
        out.poses.push({ t: t, shown: Number(slider.value), x: x, y: y, heading: Number($("robot").dataset.heading), clock: $("clock").textContent });
      }
      if (params.has("replan")) {
        const n = params.get("replan");
        const marker = timeline.querySelector('.replan[data-replan="' + n + '"]');
        if (!marker) throw new Error("no marker for replan " + n);
        marker.dispatchEvent(new MouseEvent("click", { bubbles: true }));
        const panel = $("diff");
        out.diff = {
          open: !panel.hidden && panel.getBoundingClientRect().width > 0,
          replan: panel.dataset.replan,
          title: panel.querySelector("h2").textContent,
          counts: ($("diff-counts") || { textContent: null }).textContent,
          lines: $("diff-steps").textContent.split("\n").filter(Boolean).length,
          t: T,
        };
      }
      out.notes = Array.from(document.querySelectorAll("#notes .note")).map((e) => e.textContent);
      out.title = $("title").textContent;
      out.plan = $("plan").querySelector("h2") ? $("plan").querySelector("h2").textContent : null;
    } catch (e) {
      out.errors.push(String(e && e.stack ? e.stack : e));
    }
    const write = () => ($("selftest").textContent = JSON.stringify(out));
    if (!params.has("play")) return write();
    speed.value = params.get("play"); // play for one second at that speed, with the button
    const from = T;
    $("play").click();
    setTimeout(() => {
      out.play = { from: from, to: T, button: $("play").textContent };
      $("play").click();
      write();
    }, 1000);
  }

  // ------------------------------------------------------------------ start
  window.addEventListener("error", (ev) => {
    $("selftest").textContent = JSON.stringify({ errors: [String(ev.message) + " at " + ev.lineno] });
  });
  renderHeader();
  drawRoom();
  drawTruth();
  drawLegend();
  drawTimeline();
  bind();
  const params = new URLSearchParams(location.hash.slice(1));
  if (params.has("selftest")) {
    selftest(params);
  } else {
    setTime(params.has("t") ? Number(params.get("t")) : 0);
    if (params.has("replan")) openDiff(Number(params.get("replan")));
  }
})();
