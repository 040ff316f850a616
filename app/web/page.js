/*
 * page.js - the web page of edgewise (docs/web.md): loads the WebAssembly
 * build (edgewise.js with threads when the page is cross-origin isolated,
 * else edgewise-st.js on one thread), puts the files it is given into the
 * module's file system as a Quake game directory (/game1, /game2, ...: one
 * per set of files; the shown map's is kept), and runs the
 * frame loop: input to the C side (app/web/main.c), ew_render there, the
 * RGBA frame into the canvas with putImageData.
 *
 * URL parameters: map (a .bsp or .pak on the same site), view, pos, angles
 * (as `edgewise render --pos X,Y,Z --angles P,Y,R`), time (fixed, as
 * render --time), color=true, classic=1, threads=N (0: all cores),
 * overlay=0/1, embed=1, bench=1 (with sizes=WxH,..., passes=N).
 * A page with view or pos is an embed (unless embed=0): one camera, no
 * controls but the mouse.
 */
'use strict';
(function () {
  const params = new URLSearchParams(location.search);
  const isolated = self.crossOriginIsolated === true;
  const canvas = document.getElementById('frame');
  const ctx2d = canvas.getContext('2d');
  const msgEl = document.getElementById('msg');
  const mapsEl = document.getElementById('maps');
  const colorEl = document.getElementById('color');
  const classicEl = document.getElementById('classic');
  const embed = params.get('embed') === '1' || ((params.has('view') || params.has('pos')) && params.get('embed') !== '0');
  const t0 = performance.now();
  if (embed) document.body.classList.add('embed');

  let M = null, api = null;
  let image = null, frames = 0, running = false, lastT = 0, fps = 0, fpsT = 0, fpsN = 0;
  let presentMs = 0, presentSum = 0, presentShown = 0;
  let held = 0, lookDrag = false;
  let settings = {
    color: params.get('color') === 'true' || params.get('color') === '1',
    classic: params.get('classic') === '1' || params.get('classic') === 'true',
    /* at most one per logical processor: the Web Workers the page makes at start */
    threads: params.has('threads')
      ? Math.min(Math.max(0, parseInt(params.get('threads'), 10) || 0), navigator.hardwareConcurrency || 1) : 0,
  };
  colorEl.checked = settings.color;
  classicEl.checked = settings.classic;
  let current = { name: 'builtin', view: 0 };
  let gameDir = '/game0', gameGen = 0;  /* the game directory of the map shown; each new set of files gets its own */
  const threadNote = isolated
    ? 'threads: Web Workers (cross-origin isolated)'
    : 'one thread: the page is not cross-origin isolated (no COOP/COEP headers)';

  /* What the test and other pages may read. */
  const pub = window.edgewise = {
    isolated, frames: 0, firstFrameMs: null, ready: null, bench: null, error: null,
    loads: 0,  /* sets of files handled (loaded or refused) */
    state: () => (api ? JSON.parse(api.state()) : null),
    message: () => msgEl.textContent,
    loadFiles: (files) => openFiles(files),
  };

  function show(text, isError) {
    msgEl.textContent = (text || '').replace(/\/game\d+\//g, '');  /* the page's own folders mean nothing to the reader */
    msgEl.className = isError ? 'error' : '';
  }

  function frameSize() {
    return [Math.max(320, Math.round(window.innerWidth)), Math.max(200, Math.round(window.innerHeight))];
  }

  function heapU8() {
    const buf = M.wasmMemory ? M.wasmMemory.buffer : M.HEAPU8.buffer;
    return new Uint8Array(buf);
  }

  function loadScript(src) {
    return new Promise((resolve, reject) => {
      const s = document.createElement('script');
      s.src = src;
      s.onload = resolve;
      s.onerror = () => reject(new Error('cannot load ' + src));
      document.head.appendChild(s);
    });
  }

  /* ---- files into a game directory ------------------------------------------ */

  function rmTree(path) {
    const FS = M.FS;
    let st;
    try { st = FS.stat(path); } catch (e) { return; }
    if (FS.isDir(st.mode)) {
      for (const n of FS.readdir(path)) if (n !== '.' && n !== '..') rmTree(path + '/' + n);
      FS.rmdir(path);
    } else {
      FS.unlink(path);
    }
  }

  function mkdirs(path) {
    let p = '';
    for (const part of path.split('/').filter(Boolean)) {
      p += '/' + part;
      try { M.FS.mkdir(p); } catch (e) { /* exists */ }
    }
  }

  /* The maps inside a pak's directory ("PACK", offset, length; 64-byte
   * entries: 56-byte name, offset, size); [] when it is not a pak (the
   * library says what is wrong when it opens it). */
  function pakMaps(bytes) {
    const out = [];
    if (bytes.length < 12 || String.fromCharCode(...bytes.subarray(0, 4)) !== 'PACK') return out;
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const ofs = dv.getInt32(4, true), len = dv.getInt32(8, true);
    if (ofs < 0 || len < 0 || ofs + len > bytes.length) return out;
    for (let i = 0; i + 64 <= len; i += 64) {
      let name = '';
      for (let k = 0; k < 56 && bytes[ofs + i + k]; k++) name += String.fromCharCode(bytes[ofs + i + k]);
      const m = /^maps\/([^/]+)\.bsp$/i.exec(name);
      if (m && !/^b_/i.test(m[1])) out.push(m[1]);
    }
    return out;
  }

  /* Files (name, bytes) into a new game directory (/game1, /game2, ...):
   * paks as pak0.pak, pak1.pak... (pakN names keep their order), .bsp and
   * .lit in maps/, .lmp in gfx/, .mdl and .spr in progs/.  Returns the
   * directory and the maps it can show. */
  function placeFiles(list) {
    const game = '/game' + (++gameGen);
    rmTree(game);
    mkdirs(game + '/maps'); mkdirs(game + '/gfx'); mkdirs(game + '/progs');
    const maps = [];
    const paks = list.filter(f => /\.pak$/i.test(f.name)).sort((a, b) => {
      const na = /pak(\d+)\.pak$/i.exec(a.name), nb = /pak(\d+)\.pak$/i.exec(b.name);
      return (na ? +na[1] : 1e9) - (nb ? +nb[1] : 1e9) || a.name.localeCompare(b.name);
    });
    paks.forEach((f, i) => {
      M.FS.writeFile(game + '/pak' + i + '.pak', f.bytes);
      for (const m of pakMaps(f.bytes)) if (!maps.includes(m)) maps.push(m);
    });
    for (const f of list) {
      const base = f.name.replace(/^.*[\\/]/, '');
      const ext = (/\.([^.]+)$/.exec(base) || [, ''])[1].toLowerCase();
      const dir = { bsp: 'maps', lit: 'maps', lmp: 'gfx', mdl: 'progs', spr: 'progs' }[ext];
      if (!dir) continue;
      M.FS.writeFile(game + '/' + dir + '/' + base.toLowerCase(), f.bytes);
      if (ext === 'bsp') {
        const name = base.replace(/\.bsp$/i, '').toLowerCase();
        if (!/^b_/.test(name) && !maps.includes(name)) maps.unshift(name);
      }
    }
    return { dir: game, maps };
  }

  function setMaps(maps, chosen) {
    mapsEl.textContent = '';
    for (const m of ['builtin', ...maps]) {
      const o = document.createElement('option');
      o.value = o.textContent = m;
      mapsEl.appendChild(o);
    }
    mapsEl.value = chosen;
  }

  /* Loads map `name` from the game directory dir (default: the shown map's;
   * 'builtin': the built-in scene).  On failure the message says why, the
   * map shown before stays, and so do its files. */
  function loadMap(name, view, dir) {
    dir = dir || gameDir;
    const [w, h] = frameSize();
    const rc = api.load(name, dir, view, w, h, settings.color ? 1 : 0, settings.classic ? 1 : 0, settings.threads);
    const text = api.message();
    if (rc !== 0) {
      show(text || 'cannot load ' + name, true);
      pub.error = text;
      if (dir !== gameDir) rmTree(dir);
      return false;
    }
    if (dir !== gameDir) rmTree(gameDir);
    gameDir = dir;
    current = { name, view };
    pub.error = null;
    colorEl.checked = JSON.parse(api.state()).color === 'true';
    show(text, false);
    applyCamera();
    api.setOverlay(embed ? (params.get('overlay') === '1' ? 1 : 0) : (params.get('overlay') === '0' ? 0 : 1));
    image = null;
    return true;
  }

  function applyCamera() {
    const nums = (s) => (s || '').split(',').map(Number);
    if (params.has('pos')) {
      const p = nums(params.get('pos')), a = params.has('angles') ? nums(params.get('angles')) : [0, 0, 0];
      if (p.length === 3 && a.length === 3 && p.concat(a).every(Number.isFinite))
        api.setCamera(p[0], p[1], p[2], a[0], a[1], a[2]);
      else
        show('pos and angles must be three numbers each, as X,Y,Z and PITCH,YAW,ROLL', true);
    }
    if (params.has('time')) {
      const t = Number(params.get('time'));
      if (Number.isFinite(t) && t >= 0) api.setTime(t, 1);
    }
  }

  function readFile(f) {
    return new Promise((resolve, reject) => {
      const r = new FileReader();
      r.onload = () => resolve({ name: f.name, bytes: new Uint8Array(r.result) });
      r.onerror = () => reject(r.error);
      r.readAsArrayBuffer(f);
    });
  }

  async function openFiles(fileList) {
    try {
      return await openFileSet(fileList);
    } finally {
      pub.loads++;
    }
  }

  async function openFileSet(fileList) {
    const files = Array.from(fileList || []);
    if (!files.length) return false;
    let list;
    try {
      list = await Promise.all(files.map(readFile));
    } catch (e) {
      show('cannot read the files: ' + e, true);
      return false;
    }
    const known = list.filter(f => /\.(bsp|lit|pak|lmp|mdl|spr)$/i.test(f.name));
    if (!known.length) {
      show(files.map(f => f.name).join(', ') + ': not a map (.bsp), a .pak or game data (.lit, .lmp, .mdl, .spr)', true);
      return false;
    }
    const placed = placeFiles(known), maps = placed.maps;
    if (!maps.length) {
      rmTree(placed.dir);
      show('no map among ' + known.map(f => f.name).join(', ') + ' (a .bsp, or a .pak with maps/*.bsp)', true);
      return false;
    }
    const before = Array.from(mapsEl.options).map((o) => o.value).filter((m) => m !== 'builtin');
    const ok = loadMap(maps[0], 0, placed.dir);
    setMaps(ok ? maps : before, current.name);
    return ok;
  }

  /* ?map=URL: a .pak, or a .bsp with its .lit beside and gfx/ beside its
   * maps/ folder (as the command finds them), from this same site. */
  async function openUrl(spec) {
    let url;
    try { url = new URL(spec, location.href); } catch (e) { show('map=' + spec + ': not a URL', true); return false; }
    if (url.origin !== location.origin) {
      show('map=' + spec + ': only maps on this same site can be fetched', true);
      return false;
    }
    const get = async (u, must) => {
      const r = await fetch(u);
      if (!r.ok) {
        if (must) throw new Error(u.pathname + ': ' + r.status + ' ' + r.statusText);
        return null;
      }
      return new Uint8Array(await r.arrayBuffer());
    };
    const base = url.pathname.replace(/^.*\//, '');
    try {
      const list = [{ name: base, bytes: await get(url, true) }];
      if (/\.bsp$/i.test(base)) {
        const lit = await get(new URL(base.replace(/\.bsp$/i, '.lit'), url), false);
        if (lit) list.push({ name: base.replace(/\.bsp$/i, '.lit'), bytes: lit });
        for (const g of ['palette.lmp', 'colormap.lmp']) {
          const b = await get(new URL('../gfx/' + g, url), false);
          if (b) list.push({ name: g, bytes: b });
        }
      } else if (!/\.pak$/i.test(base)) {
        show('map=' + spec + ': must name a .bsp or a .pak', true);
        return false;
      }
      const placed = placeFiles(list), maps = placed.maps;
      if (!maps.length) { rmTree(placed.dir); show(spec + ': no map in it', true); return false; }
      const view = params.has('view') ? parseInt(params.get('view'), 10) || 0 : 0;
      if (!loadMap(maps[0], view, placed.dir)) return false;
      setMaps(maps, maps[0]);
      /* the models its entities use, from the game directory around maps/
       * (progs/*.mdl, maps/b_*.bsp), as the command finds them */
      const want = [];
      for (let i = 0; api.missing(i) !== null && i < 256; i++) want.push(api.missing(i));
      if (!want.length || !/\.bsp$/i.test(base)) return true;
      const got = await Promise.all(want.map((f) => get(new URL('../' + f, url), false).catch(() => null)));
      let n = 0;
      want.forEach((f, i) => {
        if (!got[i]) return;
        mkdirs(gameDir + '/' + f.replace(/\/[^/]*$/, ''));
        M.FS.writeFile(gameDir + '/' + f, got[i]);
        n++;
      });
      return n ? loadMap(maps[0], view) : true;
    } catch (e) {
      show('map=' + spec + ': ' + e.message, true);
      return false;
    }
  }

  /* ---- the frame loop -------------------------------------------------------- */

  function drawFrame(now) {
    const dt = lastT ? Math.min(0.25, (now - lastT) / 1000) : 0;
    lastT = now;
    const [w, h] = frameSize();
    if (w !== canvas.width || h !== canvas.height) {
      if (api.resize(w, h) !== 0) show(api.message(), true);
      canvas.width = w;
      canvas.height = h;
      image = null;
    }
    api.held(held);
    const ptr = api.frame(dt, fps, presentShown);
    if (!ptr) {
      show(api.message(), true);
      return;
    }
    const st = JSON.parse(api.state());
    const p0 = performance.now();
    if (!image || image.width !== st.width || image.height !== st.height) {
      image = ctx2d.createImageData(st.width, st.height);
      canvas.width = st.width;
      canvas.height = st.height;
    }
    image.data.set(heapU8().subarray(ptr, ptr + st.width * st.height * 4));
    ctx2d.putImageData(image, 0, 0);
    presentMs = performance.now() - p0;
    presentSum += presentMs;
    frames++;
    pub.frames = frames;
    if (pub.firstFrameMs === null) {
      pub.firstFrameMs = performance.now();
      pub.firstFrameAfterScriptMs = performance.now() - t0;
      console.log('edgewise: first frame ' + pub.firstFrameMs.toFixed(1) + ' ms after the page was asked for');
    }
    fpsN++;
    if (now - fpsT >= 500) {
      fps = fpsN * 1000 / (now - fpsT);
      presentShown = presentSum / fpsN;
      presentSum = 0; fpsN = 0; fpsT = now;
    }
  }

  function loop(now) {
    if (!running) return;
    try {
      drawFrame(now);
    } catch (e) {
      show('frame: ' + e, true);
    }
    requestAnimationFrame(loop);
  }

  /* ---- input ----------------------------------------------------------------- */

  const moveBits = { KeyW: 1, ArrowUp: 1, KeyS: 2, ArrowDown: 2, KeyA: 4, ArrowLeft: 4, KeyD: 8, ArrowRight: 8,
                     Space: 16, KeyC: 32, ShiftLeft: 64, ShiftRight: 64 };

  function screenshot() {
    const name = (current.name || 'edgewise') + '_web.png';
    canvas.toBlob((blob) => {
      if (!blob) { show('the browser could not encode the PNG', true); return; }
      const a = document.createElement('a');
      a.href = URL.createObjectURL(blob);
      a.download = name;
      document.body.appendChild(a);
      a.click();
      setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
      const s = pub.state();
      show(name + ' --pos ' + s.pos.join(',') + ' --angles ' + s.angles.join(',') + ' --size ' + s.width + 'x' +
           s.height, false);
    }, 'image/png');
  }

  function setupInput() {
    if (!embed) {
      window.addEventListener('keydown', (e) => {
        if (e.target && e.target.tagName === 'INPUT' && e.target.type === 'file') return;
        const bit = moveBits[e.code];
        if (bit) { held |= bit; e.preventDefault(); }
        if (e.repeat) return;
        if (e.key === 'F12') { e.preventDefault(); screenshot(); return; }
        if (e.key === 'Escape' && document.pointerLockElement) { document.exitPointerLock(); return; }
        if (bit) return;  /* movement keys bind nothing else */
        const act = api.key(e.key);
        if (act) {
          e.preventDefault();
          const m = api.message();
          if (m) show(m, false);
        }
      });
      window.addEventListener('keyup', (e) => {
        const bit = moveBits[e.code];
        if (bit) held &= ~bit;
      });
      window.addEventListener('blur', () => { held = 0; });
    }
    canvas.addEventListener('mousedown', (e) => {
      lookDrag = true;
      if (!embed && canvas.requestPointerLock) {
        try {
          const p = canvas.requestPointerLock();
          if (p && p.catch) p.catch(() => {});
        } catch (err) { /* no pointer lock: drag to look */ }
      }
      e.preventDefault();
    });
    window.addEventListener('mouseup', () => { lookDrag = false; });
    window.addEventListener('mousemove', (e) => {
      if (document.pointerLockElement === canvas || lookDrag) api.mouse(e.movementX, e.movementY);
    });
    if (!embed) {
      const body = document.body;
      window.addEventListener('dragover', (e) => { e.preventDefault(); body.classList.add('dragging'); });
      window.addEventListener('dragleave', () => body.classList.remove('dragging'));
      window.addEventListener('drop', (e) => {
        e.preventDefault();
        body.classList.remove('dragging');
        openFiles(e.dataTransfer && e.dataTransfer.files);
      });
      document.getElementById('files').addEventListener('change', (e) => openFiles(e.target.files));
      mapsEl.addEventListener('change', () => loadMap(mapsEl.value, 0));
      /* the same map again in the other look, from where the camera is */
      const reload = () => {
        const s = pub.state();
        if (loadMap(current.name, current.view) && s && !params.has('pos'))
          api.setCamera(s.pos[0], s.pos[1], s.pos[2], s.angles[0], s.angles[1], s.angles[2]);
      };
      colorEl.addEventListener('change', () => { settings.color = colorEl.checked; reload(); });
      classicEl.addEventListener('change', () => { settings.classic = classicEl.checked; reload(); });
      document.getElementById('shot').addEventListener('click', screenshot);
      document.getElementById('helpbtn').addEventListener('click', () => {
        const h = document.getElementById('help');
        h.hidden = !h.hidden;
      });
    }
  }

  /* ---- ?bench=1 -------------------------------------------------------------- */

  function runBench() {
    const sizes = (params.get('sizes') || '640x480,1920x1080').split(',');
    const passes = parseInt(params.get('passes') || '5', 10) || 5;
    const threadSet = isolated ? [1, 0] : [1];
    const rows = [];
    const pre = document.getElementById('bench');
    for (const s of sizes) {
      const m = /^(\d+)x(\d+)$/.exec(s);
      if (!m) continue;
      for (const t of threadSet) {
        const line = api.bench(+m[1], +m[2], t, passes);
        console.log(line);
        rows.push(JSON.parse(line));
        pre.textContent += line + '\n';
      }
    }
    pub.bench = rows;
  }

  /* ---- start ------------------------------------------------------------------ */

  async function start() {
    const js = isolated ? 'edgewise.js' : 'edgewise-st.js';
    await loadScript(js);
    M = await self.EdgewiseModule({ print: (t) => console.log(t), printErr: (t) => console.warn(t) });
    const c = M.cwrap;
    api = {
      load: c('web_load', 'number', ['string', 'string', 'number', 'number', 'number', 'number', 'number', 'number']),
      resize: c('web_resize', 'number', ['number', 'number']),
      setCamera: c('web_set_camera', null, ['number', 'number', 'number', 'number', 'number', 'number']),
      setTime: c('web_set_time', null, ['number', 'number']),
      setOverlay: c('web_set_overlay', null, ['number']),
      overlayExtra: c('web_set_overlay_extra', null, ['string']),
      held: c('web_held', null, ['number']),
      mouse: c('web_mouse', null, ['number', 'number']),
      key: c('web_key', 'number', ['string']),
      frame: c('web_frame', 'number', ['number', 'number', 'number']),
      message: c('web_message', 'string', []),
      missing: c('web_missing_file', 'string', ['number']),
      state: c('web_state', 'string', []),
      bench: c('web_bench', 'string', ['number', 'number', 'number', 'number']),
      setFog: c('web_set_fog', 'number', ['number', 'number', 'number', 'number']),
    };
    api.overlayExtra(threadNote);
    let fogErr = '';
    if (params.has('fog')) {  /* fog=D,R,G,B as render's --fog, in place of the map's */
      const f = params.get('fog').split(',').map((x) => (x.trim() === '' ? NaN : Number(x)));
      if (f.length !== 4 || !f.every(Number.isFinite) || api.setFog(f[0], f[1], f[2], f[3]) < 0)
        fogErr = 'fog must be DENSITY,R,G,B: a density from 0 to 100, then three colour values from 0 to 1 (the map\'s own fog is drawn)';
    }
    mkdirs(gameDir);
    let ok = false;
    if (params.has('map')) ok = await openUrl(params.get('map'));
    if (!ok) {
      const err = msgEl.textContent;
      setMaps([], 'builtin');
      if (!loadMap('builtin', params.has('map') ? 0 : parseInt(params.get('view') || '0', 10) || 0)) return;
      if (err) show(err + '\n(showing the built-in scene)', true);
    }
    if (!params.has('map') && !embed)
      show('the built-in scene: drop a .bsp (with its .lit), a .pak or several files on the page, or open them ' +
           'above (' + (isolated ? 'threads on every core' : threadNote) + ')', false);
    if (fogErr) show(fogErr, true);
    setupInput();
    if (params.get('bench') === '1') runBench();
    running = true;
    requestAnimationFrame(loop);
  }

  pub.ready = start().then(() => true, (e) => {
    show('edgewise could not start: ' + e, true);
    pub.error = String(e);
    return false;
  });
})();
