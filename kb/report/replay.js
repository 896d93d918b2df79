// kitkb's replay of a run on its page (kb/report/replay.py makes the data and inlines this file).
// Plays the run's CRCL commands on the cell's clock: the tool tip along each command's path at
// the speed in force, the objects it holds with it, failures when they were found, and the
// Metrics & Settings panel after each completed command (the first paper's Fig. 14).
// Keys (as the kittingViewer's): g the next action, n the next command, p play / pause.
// window.kitkbReplays[id]: play(), pause(), command(), action(), seek(t), state().
(() => {
  if (window.kitkbReplays) return;
  const players = window.kitkbReplays = {};
  let current = null;

  const fmt = v => (typeof v === 'number') ? (Number.isInteger(v) ? String(v) : v.toFixed(3)) : String(v);

  function Player(id, data, gd, root) {
    const rows = data.rows, n = rows.length;
    const from = [];  // where the tip stands when each command starts
    let here = data.start;
    for (const r of rows) { from.push(here); if (r[4] && r[4].length === 3) here = r[4]; }
    const index = {};
    gd.data.forEach((t, k) => { if (t.meta) index[t.meta] = k; });
    const state = {t: 0, done: 0, playing: false, last: null};
    const clock = root.querySelector('.replay-clock'), slider = root.querySelector('input[type=range]');
    const playButton = root.querySelector('[data-do=play]');
    let shown = false;

    // the first row whose end is after t (binary search); n when none
    function rowAfter(t) {
      let lo = 0, hi = n;
      while (lo < hi) { const mid = (lo + hi) >> 1; if (rows[mid][3] > t) hi = mid; else lo = mid + 1; }
      return lo;
    }
    function completed(t) {  // commands completed by time t
      let lo = 0, hi = n;
      while (lo < hi) { const mid = (lo + hi) >> 1; if (rows[mid][3] <= t + 1e-9) lo = mid + 1; else hi = mid; }
      return lo;
    }
    function tipAt(t) {
      const k = rowAfter(t);
      if (k >= n) return here;
      const r = rows[k];
      if (t <= r[2] || !r[5].length || r[3] <= r[2]) return from[k];
      const pts = [from[k], ...r[5]];
      const lens = [];
      let total = 0;
      for (let i = 1; i < pts.length; i++) { const d = Math.hypot(...[0, 1, 2].map(a => pts[i][a] - pts[i - 1][a])); lens.push(d); total += d; }
      let go = total * (t - r[2]) / (r[3] - r[2]);  // the speed in force throughout the move
      for (let i = 1; i < pts.length; i++) {
        if (go <= lens[i - 1] || i === pts.length - 1) {
          const f = lens[i - 1] > 0 ? Math.min(1, go / lens[i - 1]) : 1;
          return [0, 1, 2].map(a => pts[i - 1][a] + f * (pts[i][a] - pts[i - 1][a]));
        }
        go -= lens[i - 1];
      }
      return r[4];
    }
    function cornersAt(obj, t, tip) {
      let seg = obj.segments[0];
      for (const s of obj.segments) { if (s[0] <= t + 1e-9) seg = s; else break; }
      if (seg[1] === 'gone') return null;
      if (seg[1] === 'rest') return seg[2];
      return seg[2].map(c => [c[0] + tip[0], c[1] + tip[1], c[2] + tip[2]]);
    }
    function enter() {  // the replay's traces shown, the states' objects hidden (their tables and boxes kept)
      if (shown) return;
      shown = true;
      const vis = gd.data.map(tr => {
        if (tr.meta && String(tr.meta).startsWith('replay')) return true;
        if (tr.meta === 'path') return true;
        return tr.type === 'mesh3d' && tr.legendgroup === 'initial' && String(tr.name).startsWith('tables');
      });
      Plotly.restyle(gd, {visible: vis});
    }
    function render() {
      const t = state.t, tip = tipAt(t);
      const xs = [], ys = [], zs = [], where = {};
      for (const obj of data.objects) {
        const c = cornersAt(obj, t, tip);
        where[obj.name] = c ? [0, 1, 2].map(a => c.reduce((s, p) => s + p[a], 0) / 8) : null;
        for (let v = 0; v < 8; v++) {
          const p = c ? c[v] : tip;  // gone: a point, no area
          xs.push(p[0]); ys.push(p[1]); zs.push(p[2]);
        }
      }
      const fs = data.failures.filter(f => f.t <= t + 1e-9 && f.at);
      const moving = [index['replay-objects'], index['replay-tool']];
      if (!moving.includes(undefined))  // one redraw for the objects and the tool
        Plotly.restyle(gd, {x: [xs, [tip[0]]], y: [ys, [tip[1]]], z: [zs, [tip[2] + 0.01]]}, moving);
      const k = index['replay-failures'];
      if (k !== undefined && fs.length !== state.failuresShown) {  // the failures: only when they change
        state.failuresShown = fs.length;
        Plotly.restyle(gd, {x: [fs.map(f => f.at[0])], y: [fs.map(f => f.at[1])], z: [fs.map(f => f.at[2] + 0.04)],
                            text: [fs.map(f => f.label)], hovertext: [fs.map(f => f.text)],
                            'marker.color': [fs.map(f => f.recovered ? '#e67e22' : '#c0392b')]}, [k]);
      }
      state.last = {tip, where, failures: fs.map(f => f.label)};
      panel();
    }
    function panel() {
      const k = state.done - 1, r = k >= 0 ? rows[k] : null;
      clock.textContent = `${state.t.toFixed(3)} s of ${data.t_end.toFixed(3)} s · command ${state.done} of ${n}`;
      slider.value = String(state.t);
      root.querySelector('.replay-command').textContent = r ? `action ${r[0]}: ${r[1]}` : 'before the first command';
      data.metrics.forEach((m, i) => {
        const cell = root.querySelector(`td[data-metric="${m}"]`);
        if (cell) cell.textContent = r ? fmt(r[6][i]) : '0';
      });
      const s = r ? {...data.settings[r[7]], position: r[4].map(v => v.toFixed(4)).join(', ')} : {};
      root.querySelectorAll('td[data-setting]').forEach(cell => {
        const v = s[cell.dataset.setting];
        cell.textContent = v === undefined ? '–' : fmt(v);
      });
      const fs = data.failures.filter(f => f.t <= state.t + 1e-9);
      root.querySelector('.replay-failures').textContent = fs.length
        ? 'failures so far: ' + fs.map(f => `${f.label} ${f.mode}${f.recovered ? ' (recovered)' : ''}`).join('; ') : 'no failure so far';
    }
    function seek(t) {
      enter();
      state.t = Math.max(0, Math.min(data.t_end, Number(t)));
      state.done = completed(state.t);
      if (state.t >= data.t_end) state.done = n;
      render();
    }
    function toCommand(k) {
      enter();
      state.done = Math.max(0, Math.min(n, k));
      state.t = state.done ? rows[state.done - 1][3] : 0;
      render();
    }
    function command() { pause(); toCommand(state.done + 1); }
    function action() {
      pause();
      if (state.done >= n) return;
      let k = state.done;
      const a = rows[k][0];
      while (k < n && rows[k][0] === a) k++;
      toCommand(k);
    }
    function frame(now) {
      if (!state.playing) return;
      const rate = Number(root.querySelector('select[data-do=rate]').value) || 1;
      const dt = state.before === undefined ? 0 : (now - state.before) / 1000;
      state.before = now;
      seek(state.t + dt * rate);
      if (state.t >= data.t_end) { pause(); return; }
      requestAnimationFrame(frame);
    }
    function play() {
      enter();
      if (state.t >= data.t_end) seek(0);
      state.playing = true; state.before = undefined; playButton.textContent = '❚❚ pause';
      requestAnimationFrame(frame);
    }
    function pause() { state.playing = false; playButton.textContent = '▶ play'; }
    const api = {play, pause, command, action, seek, toCommand,
                 state: () => ({t: state.t, done: state.done, commands: n, playing: state.playing, ...(state.last || {}),
                               panel: Object.fromEntries([...root.querySelectorAll('td[data-metric]')].map(c => [c.dataset.metric, c.textContent]))})};
    root.addEventListener('click', e => {
      current = api;
      const what = e.target.dataset && e.target.dataset.do;
      if (what === 'play') state.playing ? pause() : play();
      else if (what === 'command') command();
      else if (what === 'action') action();
      else if (what === 'restart') { pause(); toCommand(0); }
    });
    slider.addEventListener('input', () => { current = api; pause(); seek(slider.value); });
    root.querySelector('.replay-controls').hidden = false;
    api.readyMs = performance.now();  // since navigation started
    players[id] = api;
    current = current || api;
    panel();
    return api;
  }

  document.addEventListener('keydown', e => {
    const typing = /SELECT|TEXTAREA/.test(e.target.tagName) || (e.target.tagName === 'INPUT' && e.target.type !== 'range');
    if (!current || e.ctrlKey || e.metaKey || e.altKey || typing) return;
    if (e.key === 'g') current.action();
    else if (e.key === 'n') current.command();
    else if (e.key === 'p') current.state().playing ? current.pause() : current.play();
  });

  // each replay starts once its 3-D view is drawn: at once if it is, else when the page says it drew
  // its figures (<body data-drawn>, kb.report.html's DRAW; no polling: a hidden tab's timers are slowed)
  function start() {
    for (const el of document.querySelectorAll('script[type="application/json"][data-replay]')) {
      const id = el.dataset.replay, gd = document.getElementById(id), root = document.getElementById(el.dataset.root);
      if (players[id] || !gd || !root || !gd._fullLayout || !window.Plotly) continue;
      try { Player(id, JSON.parse(el.textContent), gd, root); }
      catch (err) { console.error('kitkb replay ' + id + ': ' + err); }
    }
  }
  function watch() {
    new MutationObserver(start).observe(document.body, {attributes: true, attributeFilter: ['data-drawn']});
    start();
  }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', watch); else watch();
})();
