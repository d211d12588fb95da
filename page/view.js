// The page of `yarnvox view`: shows the JPEG frames the server sends over a
// WebSocket, turns mouse, wheel and keys into camera messages (at most one
// an animation frame; the server draws only the latest), and keeps the
// camera and mode in the address (#az=..&el=..) so a link reopens the view.
// For a garment, when the camera stops the page asks the server to voxelize
// what it sees (finer voxels where zoomed in), which the frames then show.
// The transfer function (a preset and its opacity) and a garment's twist
// are set from the controls or keys and kept in the address too. Cameras
// sent while input goes on say they are moving (the server may then draw
// fewer slices where a frame would be late); when it stops, the camera is
// sent once more, not moving, for the picture at full quality. `g` turns
// that off: every frame at full quality.
'use strict';
(() => {
  const defaults = { az: 30, el: 20, d: 4, px: 0, py: 0 };
  const cam = Object.assign({}, defaults);
  let mode = null, modes = [], hello = null, seq = 0, blend = false, moving = false, degrade = true;
  // The look: a transfer-function preset, its opacity scale as a power of
  // two, and the twist as the fibres' lean at the yarn's surface (twist
  // times yarn radius: the tangent of the helix angle there). null: the server's.
  const look = { tf: null, op: 0, tw: null };
  let socket = null, dirty = false, pendingStats = null, lastUrl = null, pendingShot = null;
  const sentAt = new Map(); // seq -> when sent, for input-to-picture time
  const img = document.getElementById('frame');
  const stage = document.getElementById('stage');
  const overlay = document.getElementById('overlay');
  const notice = document.getElementById('notice');
  // What tests (tests/browser) and the benchmark read.
  const view = window.yvView = { frames: 0, stats: null, shownSeq: -1, latencyMs: null, notices: [],
                                 voxelize: [], autoVoxelize: true, stopToDetailMs: null, stopToFinalMs: null,
                                 movingFrames: 0 };
  // No camera input for this long: the camera has stopped. Short, since a newer
  // view gives up the runs of the last (their next zoom region boundary).
  const stopMs = 150;
  let stopTimer = null, twistTimer = null, askedAt = null, lastDetailId = 0;

  const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));
  const round = (v) => Math.round(v * 1000) / 1000;

  function readHash() {
    const h = new URLSearchParams(location.hash.slice(1));
    for (const k of Object.keys(defaults)) {
      const v = Number(h.get(k));
      if (h.has(k) && Number.isFinite(v)) cam[k] = v;
    }
    cam.el = clamp(cam.el, -89.9, 89.9);
    cam.d = clamp(cam.d, 0.05, 100);
    cam.px = clamp(cam.px, -50, 50);
    cam.py = clamp(cam.py, -50, 50);
    cam.az = ((cam.az % 360) + 360) % 360;
    blend = h.get('blend') === '1';
    degrade = h.get('deg') !== '0';
    if (h.has('tf')) look.tf = h.get('tf');
    const op = Number(h.get('op')), tw = Number(h.get('tw'));
    if (h.has('op') && Number.isFinite(op)) look.op = clamp(op, -6, 6);
    if (h.has('tw') && Number.isFinite(tw)) look.tw = clamp(tw, -1, 1);
    return h.get('mode');
  }

  function writeHash() {
    const h = new URLSearchParams();
    for (const k of Object.keys(defaults)) h.set(k, String(round(cam[k])));
    if (mode) h.set('mode', mode);
    if (blend) h.set('blend', '1');
    if (!degrade) h.set('deg', '0');
    if (look.tf) h.set('tf', look.tf);
    if (look.op !== 0) h.set('op', String(look.op));
    if (look.tw !== null) h.set('tw', String(round(look.tw)));
    history.replaceState(null, '', '#' + h.toString());
  }

  function send(message) {
    if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
  }

  function cameraChanged() {
    cam.az = ((cam.az % 360) + 360) % 360;
    cam.el = clamp(cam.el, -89.9, 89.9);
    cam.d = clamp(cam.d, 0.05, 100);
    cam.px = clamp(cam.px, -50, 50);
    cam.py = clamp(cam.py, -50, 50);
    moving = true;
    if (!dirty) { dirty = true; requestAnimationFrame(flush); }
    clearTimeout(stopTimer);
    stopTimer = setTimeout(cameraStopped, stopMs);
  }

  // The camera once more, not moving (the picture at full quality), then
  // what it sees voxelized where that is on.
  function cameraStopped() {
    moving = false;
    flush();
    if (view.autoVoxelize) voxelizeView();
  }

  // Only a garment's view can voxelize (the hello gives its voxel size).
  function voxelizeView() {
    if (!hello || hello.voxelSize === null || hello.voxelSize === undefined) return;
    askedAt = performance.now();
    view.stopToDetailMs = view.stopToFinalMs = null;
    send({ type: 'voxelize-view' });
  }

  function flush() {
    dirty = false;
    seq += 1;
    sentAt.set(seq, performance.now());
    if (sentAt.size > 256) sentAt.delete(sentAt.keys().next().value);
    view.seq = seq;
    send({ type: 'camera', azimuth: round(cam.az), elevation: round(cam.el), distance: round(cam.d),
           panX: round(cam.px), panY: round(cam.py), seq, moving });
    writeHash();
  }

  function sendSize() {
    const dpr = Math.min(window.devicePixelRatio || 1, 2);
    const w = clamp(Math.round(stage.clientWidth * dpr), 16, 4096);
    const h = clamp(Math.round(stage.clientHeight * dpr), 16, 4096);
    view.size = [w, h];
    send({ type: 'size', width: w, height: h });
  }

  function setMode(m) {
    if (!modes.includes(m)) return;
    mode = m;
    send({ type: 'mode', mode });
    writeHash();
  }

  // The twist in the server's units (radians per world unit) from the lean at the surface.
  const twistOf = (lean) => lean / hello.yarnRadius;
  // The lean shown: the page's, else the garment's own.
  const leanNow = () => (look.tw !== null ? look.tw : hello.twist * hello.yarnRadius);
  // A garment's slices and voxels may be blended in one picture (not two volumes).
  const blends = () => hello && hello.sideBySide && !hello.beside;
  const twistable = () => hello && hello.twist !== null && hello.twist !== undefined && hello.yarnRadius > 0;

  function sendLook() {
    if (!hello) return;
    send({ type: 'transfer', preset: look.tf, opacity: Math.pow(2, look.op) });
    if (twistable() && look.tw !== null) send({ type: 'twist', twist: twistOf(look.tw) });
    showControls();
    writeHash();
  }

  function showControls() {
    const select = document.getElementById('transfer');
    if (select.options.length !== hello.transferPresets.length) {
      select.textContent = '';
      for (const p of hello.transferPresets) select.add(new Option(p, p));
    }
    select.value = look.tf;
    document.getElementById('opacity').value = String(look.op);
    document.getElementById('opacity-value').textContent = 'x' + Number(Math.pow(2, look.op).toPrecision(3));
    document.getElementById('twist-control').hidden = !twistable();
    if (twistable()) {
      const lean = leanNow();
      document.getElementById('twist').value = String(lean);
      document.getElementById('twist-value').textContent = (Math.atan(lean) * 180 / Math.PI).toFixed(1) +
        ' deg at the surface, ' + Number(twistOf(lean).toPrecision(3)) + ' rad a unit';
    }
  }

  function setLook(change) {
    Object.assign(look, change);
    if (!hello.transferPresets.includes(look.tf)) look.tf = hello.transfer;
    look.op = clamp(look.op, -6, 6);
    if (look.tw !== null) look.tw = clamp(Math.round(look.tw * 100) / 100, -1, 1);
    sendLook();
    // A twist changes what voxelizing the view would give: ask again once it has settled.
    if ('tw' in change && view.autoVoxelize) { clearTimeout(twistTimer); twistTimer = setTimeout(voxelizeView, stopMs); }
  }

  function showNotice(text) {
    view.notices.push(text);
    notice.textContent = text;
    notice.style.display = 'block';
    clearTimeout(showNotice.timer);
    showNotice.timer = setTimeout(() => { notice.style.display = 'none'; }, 5000);
  }

  function showOverlay(s) {
    const net = view.latencyMs === null ? '' : '   input to picture ' + view.latencyMs.toFixed(1) + ' ms' +
      ' (network and waiting ' + Math.max(0, view.latencyMs - s.renderMs - s.encodeMs).toFixed(1) + ' ms)';
    const which = hello && hello.beside ? 'left: ' + hello.name + ', right: ' + hello.beside + ', ' + s.mode
      : hello && hello.sideBySide ? (s.blend ? 'slices and ' + s.mode + ' blended' : 'left: slices, right: ' + s.mode) : s.mode;
    overlay.textContent =
      (hello ? hello.name + '   ' : '') + which + '   ' + s.width + 'x' + s.height + '   frame ' + s.frame + '\n' +
      'render ' + s.renderMs.toFixed(1) + ' ms (draw ' + s.drawMs.toFixed(1) + ')   encode ' + s.encodeMs.toFixed(1) +
      ' ms' + net + '\n' +
      (s.detail && s.detail.shown
        ? s.detail.activeVoxels.toLocaleString('en') + ' active voxels of the view, voxel ' + s.detail.voxelSize +
          ' (voxelized in ' + s.detail.seconds.toFixed(2) + ' s)'
        : s.activeVoxels.toLocaleString('en') + ' active voxels') + '   level ' + s.level +
      (s.slices ? '   ' + s.slices.toLocaleString('en') + ' slices' : '') +
      (s.sliceLod !== null && s.sliceLod !== undefined
        ? ' (level of detail ' + s.sliceLod + ' px' + (s.degraded ? ', coarser while moving' : '') + ')' : '') +
      (s.degrade ? '' : '   full quality while moving (g)') + '   ' +
      (s.bytes / 1024).toFixed(1) + ' KiB a frame   GPU: ' + (s.gpuBytes / 1048576).toFixed(0) + ' MiB of bricks' +
      (s.gpuFreeBytes >= 0 ? ', ' + (s.gpuFreeBytes / 1073741824).toFixed(1) + ' GiB free' : '') +
      (hello ? '\n' + hello.renderer : '') + (hello && hello.voxelSize ? '   voxel ' + hello.voxelSize.toPrecision(3) : '') +
      '\nmodes: ' + modes.map((m, i) => (i + 1) + ' ' + m).join('  ');
  }

  // A scale bar at the point looked at: a round length (1, 2 or 5 times a
  // power of ten) of 60 to 150 screen pixels, in the garment's units (or voxels).
  function showRuler(s) {
    const ruler = document.getElementById('ruler');
    if (!(s.pixelSize > 0)) { ruler.style.display = 'none'; return; }
    // The frame's pixels are shown at the stage's CSS size (the image is scaled to fit).
    const cssPerPixel = Math.min(stage.clientWidth / s.width, stage.clientHeight / s.height);
    const perCss = s.pixelSize / cssPerPixel;
    const want = 100 * perCss;
    const p = Math.pow(10, Math.floor(Math.log10(want)));
    const length = [1, 2, 5, 10].map((k) => k * p).find((l) => l / perCss >= 60) || 10 * p;
    document.getElementById('ruler-bar').style.width = (length / perCss).toFixed(0) + 'px';
    document.getElementById('ruler-label').textContent =
      Number(length.toPrecision(3)).toString() + (s.pixelUnits === 'world' ? ' (garment units)' : ' voxels');
    ruler.style.display = 'block';
    view.ruler = { length, pixels: length / perCss, units: s.pixelUnits };
  }

  function onText(data) {
    let m;
    try { m = JSON.parse(data); } catch (e) { return; }
    if (m.type === 'hello') {
      hello = m;
      modes = m.modes;
      const wanted = readHash();
      mode = modes.includes(wanted) ? wanted : m.mode;
      if (!m.transferPresets.includes(look.tf)) look.tf = m.transfer;
      sendSize();
      send({ type: 'mode', mode });
      if (blends()) send({ type: 'layout', blend });
      if (!degrade) send({ type: 'quality', degrade });
      sendLook();
      flush();
    } else if (m.type === 'stats') {
      pendingStats = m;
    } else if (m.type === 'screenshot') {
      pendingShot = m;
    } else if (m.type === 'notice') {
      showNotice(m.text);
    } else if (m.type === 'voxelize') {
      view.voxelize.push(m);
      if (m.state === 'running') {
        showNotice((m.pass === 'first' ? 'voxelizing what the camera sees, a coarse pass first: voxel '
                                        : 'voxelizing what the camera sees: voxel ') + m.voxelSize + ', box ' + m.bboxWorld);
      }
      if (m.state === 'failed') showNotice('voxelizing the view failed: ' + m.text);
      if (m.state === 'saved') showNotice('saved ' + (m.workDir ? m.workDir + ' and ' : '') + m.vdb + '; the same: ' + m.commandText);
    }
  }

  // A screenshot: saved by the browser as a download, never shown in place of the view.
  function onScreenshot(blob, m) {
    const url = URL.createObjectURL(new Blob([blob], { type: 'image/jpeg' }));
    const a = document.createElement('a');
    a.href = url;
    a.download = 'yarnvox-view-' + m.width + 'x' + m.height + '.jpg';
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 60000);
    view.screenshot = { width: m.width, height: m.height, bytes: blob.byteLength };
    showNotice('screenshot ' + m.width + 'x' + m.height + ' saved by the browser');
  }

  // Twice the frame's size, at most 4096 a side, the same shape.
  function takeScreenshot() {
    if (!view.size) return;
    const k = Math.min(2, 4096 / view.size[0], 4096 / view.size[1]);
    send({ type: 'screenshot', width: Math.max(16, Math.floor(view.size[0] * k)), height: Math.max(16, Math.floor(view.size[1] * k)) });
  }

  function onFrame(blob) {
    if (pendingShot) { const m = pendingShot; pendingShot = null; onScreenshot(blob, m); return; }
    const s = pendingStats;
    pendingStats = null;
    const url = URL.createObjectURL(new Blob([blob], { type: 'image/jpeg' }));
    img.onload = () => {
      if (lastUrl) URL.revokeObjectURL(lastUrl);
      lastUrl = url;
      view.frames += 1;
      if (s) {
        const t = sentAt.get(s.seq);
        if (t !== undefined) { view.latencyMs = performance.now() - t; sentAt.delete(s.seq); }
        view.stats = s;
        if (s.moving) view.movingFrames += 1;
        view.shownSeq = s.seq;
        view.shownMode = s.mode;
        // The first picture of the view's run (a coarse pass where it comes in two), and its final one.
        if (s.detail && s.detail.shown && s.detail.id !== lastDetailId) {
          lastDetailId = s.detail.id;
          if (askedAt !== null) {
            if (view.stopToDetailMs === null) view.stopToDetailMs = performance.now() - askedAt;
            if (s.detail.final && view.stopToFinalMs === null) view.stopToFinalMs = performance.now() - askedAt;
          }
        }
        showOverlay(s);
        showRuler(s);
      }
    };
    img.src = url;
  }

  function connect() {
    socket = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
    socket.binaryType = 'arraybuffer';
    socket.onmessage = (e) => (typeof e.data === 'string' ? onText(e.data) : onFrame(e.data));
    socket.onclose = () => { overlay.textContent = 'disconnected: is yarnvox view still running? (reload to reconnect)'; };
  }

  // True once the picture shown is of the latest camera, mode and size asked for (tests wait on it).
  view.settled = () => view.stats !== null && view.shownSeq === seq && view.shownMode === mode &&
    !moving && view.stats.degrade === degrade &&
    (!blends() || view.stats.blend === blend) &&
    (!hello || (view.stats.transfer === look.tf && Math.abs(view.stats.opacity - Math.pow(2, look.op)) < 1e-9 &&
                (!twistable() || look.tw === null || Math.abs(view.stats.twist - twistOf(look.tw)) < 1e-9))) &&
    view.size && view.stats.width === view.size[0] && view.stats.height === view.size[1];

  let drag = null;
  stage.addEventListener('contextmenu', (e) => e.preventDefault());
  stage.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
    stage.setPointerCapture(e.pointerId);
    stage.classList.add('dragging');
  });
  stage.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      // A pixel moves the point looked at by about a pixel's worth of the sphere at the centre.
      const k = 2 * cam.d * Math.tan(Math.PI / 12) / Math.max(1, stage.clientHeight);
      cam.px -= dx * k; cam.py += dy * k;
    } else {
      cam.az -= dx * 0.4; cam.el += dy * 0.4;
    }
    cameraChanged();
  });
  const endDrag = () => { drag = null; stage.classList.remove('dragging'); };
  stage.addEventListener('pointerup', endDrag);
  stage.addEventListener('pointercancel', endDrag);
  stage.addEventListener('wheel', (e) => {
    e.preventDefault();
    const unit = e.deltaMode === 1 ? 16 : e.deltaMode === 2 ? 400 : 1;
    if (e.shiftKey && !e.ctrlKey) {
      const k = 2 * cam.d * Math.tan(Math.PI / 12) / Math.max(1, stage.clientHeight);
      cam.px += e.deltaX * unit * k; cam.py -= e.deltaY * unit * k;
    } else {
      // A pinch on a touchpad arrives as a wheel with ctrlKey and small steps: the same zoom, faster.
      cam.d *= Math.exp(e.deltaY * unit * (e.ctrlKey ? 0.01 : 0.0015));
    }
    cameraChanged();
  }, { passive: false });
  document.getElementById('transfer').addEventListener('change', (e) => setLook({ tf: e.target.value }));
  document.getElementById('opacity').addEventListener('input', (e) => setLook({ op: Number(e.target.value) }));
  document.getElementById('twist').addEventListener('input', (e) => setLook({ tw: Number(e.target.value) }));
  window.addEventListener('keydown', (e) => {
    if (e.altKey || e.metaKey || e.ctrlKey) return;
    if (e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement) e.target.blur();
    const step = 5, k = 0.05 * cam.d;
    const keys = {
      ArrowLeft: () => (e.shiftKey ? (cam.px -= k) : (cam.az += step)),
      ArrowRight: () => (e.shiftKey ? (cam.px += k) : (cam.az -= step)),
      ArrowUp: () => (e.shiftKey ? (cam.py += k) : (cam.el += step)),
      ArrowDown: () => (e.shiftKey ? (cam.py -= k) : (cam.el -= step)),
      '+': () => (cam.d /= 1.1), '=': () => (cam.d /= 1.1), '-': () => (cam.d *= 1.1),
      r: () => Object.assign(cam, defaults),
    };
    if (keys[e.key]) { keys[e.key](); cameraChanged(); e.preventDefault(); return; }
    if (/^[1-9]$/.test(e.key) && modes[Number(e.key) - 1]) { setMode(modes[Number(e.key) - 1]); return; }
    if (e.key === 'v') voxelizeView();
    if (e.key === 'a') { view.autoVoxelize = !view.autoVoxelize; showNotice('voxelize on stop: ' + (view.autoVoxelize ? 'on' : 'off')); }
    if (e.key === 's') send({ type: 'save-view', workDir: false });
    if (e.key === 'p') takeScreenshot();
    if (e.key === 'b' && blends()) { blend = !blend; send({ type: 'layout', blend }); writeHash(); }
    if (e.key === 'g') {
      degrade = !degrade;
      send({ type: 'quality', degrade });
      writeHash();
      showNotice(degrade ? 'while moving: fewer slices where a frame would be late' : 'while moving: every frame at full quality');
    }
    if (e.key === 'W') send({ type: 'save-view', workDir: true });
    if (e.key === 't' && hello) {
      const p = hello.transferPresets;
      setLook({ tf: p[(p.indexOf(look.tf) + 1) % p.length] });
    }
    if ((e.key === 'o' || e.key === 'O') && hello) setLook({ op: look.op + (e.key === 'O' ? 0.5 : -0.5) });
    if ((e.key === '[' || e.key === ']') && twistable()) setLook({ tw: leanNow() + (e.key === ']' ? 0.05 : -0.05) });
    if (e.key === 'h') { const h = document.getElementById('help'); h.style.display = h.style.display === 'none' ? '' : 'none'; }
    // The controls stay hidden until asked for: they would take the drags of a small window.
    if (e.key === 'c') { const c = document.getElementById('controls'); c.hidden = !c.hidden; }
  });
  let resizeTimer = null;
  window.addEventListener('resize', () => { clearTimeout(resizeTimer); resizeTimer = setTimeout(sendSize, 150); });

  readHash();
  connect();
})();
