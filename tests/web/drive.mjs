/*
 * drive.mjs - drives the web page (app/web/) in Debian's chromium, headless,
 * through puppeteer-core (no browser download), for tests/test_web.c.
 *
 *   node drive.mjs SPEC.json
 *
 * SPEC: { web: the built page (build-web/web), site: a folder served under
 * /site (maps/, gfx/ as a map archive has them), chromium: the browser,
 * out: where to write, cases: [{ name, isolated, query, files, width,
 * height }], checks: true to run the input, bad-file and bench checks,
 * lonemap: a .bsp to give the page without game data }.
 * For each case the page is opened at WIDTHxHEIGHT with ?QUERY (and FILES
 * given to its file input), and once it has drawn its frame the canvas's
 * RGBA bytes are written to OUT/NAME.rgba and its state to OUT/NAME.json.
 * The other checks print "ok ..." or "FAIL ..." lines; the exit code is
 * 1 if any failed.  Two servers (serve.mjs): one cross-origin isolated
 * (threads), one not (the page's one-thread fallback).
 */
import fs from 'node:fs';
import path from 'node:path';
import { spawn } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const { default: puppeteer } = await import(path.join(here, 'node_modules/puppeteer-core/lib/esm/puppeteer/puppeteer-core.js'));
const spec = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
let failed = 0;
const ok = (cond, what) => {
  console.log((cond ? 'ok ' : 'FAIL ') + what);
  if (!cond) failed++;
};

function serve(isolated) {
  return new Promise((resolve, reject) => {
    const args = [path.join(spec.web, 'serve.mjs'), '--root', spec.web, '--port', '0', '--mount', '/site=' + spec.site];
    if (!isolated) args.push('--no-isolation');
    const p = spawn(process.execPath, args, { stdio: ['ignore', 'pipe', 'inherit'] });
    p.stdout.once('data', (d) => {
      const m = /http:\/\/[^ ]+\//.exec(String(d));
      m ? resolve({ proc: p, url: m[0] }) : reject(new Error('serve.mjs: ' + d));
    });
    p.on('error', reject);
  });
}

const servers = { true: await serve(true), false: await serve(false) };
const browser = await puppeteer.launch({
  executablePath: spec.chromium, headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
});

async function open(isolated, query, width, height, cores) {
  const page = await browser.newPage();
  if (cores) {  /* a machine of that many logical processors, as the page sees it */
    const cdp = await page.createCDPSession();
    await cdp.send('Emulation.setHardwareConcurrencyOverride', { hardwareConcurrency: cores });
  }
  await page.setViewport({ width, height });
  page.on('pageerror', (e) => console.log('page error: ' + e.message));
  page.on('console', (m) => { if (/^edgewise|error/i.test(m.text())) console.log('console: ' + m.text()); });
  await page.goto(servers[isolated].url + 'index.html' + (query ? '?' + query : ''));
  const started = await page.evaluate(() => window.edgewise.ready);
  if (!started) throw new Error('the page did not start: ' + await page.evaluate(() => window.edgewise.error));
  return page;
}

/* Waits until n more frames have been drawn. */
async function frames(page, n) {
  const f0 = await page.evaluate(() => window.edgewise.frames);
  await page.waitForFunction((f) => window.edgewise.frames >= f, { timeout: 60000 }, f0 + n);
}

async function upload(page, files) {
  const input = await page.$('#files');
  const before = await page.evaluate(() => window.edgewise.loads);
  await input.uploadFile(...files);
  /* openFiles runs on the change event: wait until it has loaded (or
   * refused) them, then for frames after it */
  await page.waitForFunction((b) => window.edgewise.loads > b, { timeout: 60000 }, before);
  await frames(page, 2);
}

async function canvasRGBA(page) {
  const b64 = await page.evaluate(() => {
    const c = document.getElementById('frame');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let s = '';
    for (let i = 0; i < d.length; i += 0x8000) s += String.fromCharCode.apply(null, d.subarray(i, i + 0x8000));
    return btoa(s);
  });
  return Buffer.from(b64, 'base64');
}

const state = (page) => page.evaluate(() => window.edgewise.state());
const message = (page) => page.evaluate(() => window.edgewise.message());

try {
  for (const c of spec.cases) {
    const t0 = Date.now();
    const page = await open(c.isolated, c.query, c.width, c.height);
    if (c.files) await upload(page, c.files);
    await frames(page, 2);
    const st = await state(page);
    const info = { state: st, message: await message(page), isolated: await page.evaluate(() => window.edgewise.isolated),
                   firstFrameMs: await page.evaluate(() => window.edgewise.firstFrameMs),
                   canvas: await page.evaluate(() => [document.getElementById('frame').width, document.getElementById('frame').height]) };
    fs.writeFileSync(path.join(spec.out, c.name + '.rgba'), await canvasRGBA(page));
    fs.writeFileSync(path.join(spec.out, c.name + '.json'), JSON.stringify(info));
    console.log(`case ${c.name}: ${st.map} ${st.width}x${st.height} ${st.color} threads ${st.threads} ` +
                `(isolated ${info.isolated}), first frame ${info.firstFrameMs.toFixed(0)} ms, ${Date.now() - t0} ms in all`);
    if (c.screenshot) await page.screenshot({ path: path.join(spec.out, c.name + '.png') });
    await page.close();
  }

  if (spec.checks) {
    /* keyboard and mouse move the camera (the main page, the built-in scene) */
    const page = await open(true, 'time=0', 640, 480);
    await frames(page, 2);
    const s0 = await state(page);
    await page.focus('#frame');
    await page.keyboard.down('w');
    await new Promise((r) => setTimeout(r, 600));
    await page.keyboard.up('w');
    await frames(page, 2);
    const s1 = await state(page);
    const moved = Math.hypot(s1.pos[0] - s0.pos[0], s1.pos[1] - s0.pos[1], s1.pos[2] - s0.pos[2]);
    ok(moved > 20, `W held 0.6 s moves the camera ${moved.toFixed(1)} units (from ${s0.pos} to ${s1.pos})`);
    await page.keyboard.press('2');
    await frames(page, 2);
    const s2 = await state(page);
    ok(s2.view === 2 && s2.pos.join() !== s1.pos.join(), `key 2 goes to view 2 (view ${s2.view}, pos ${s2.pos})`);
    await page.keyboard.press('F3');
    await frames(page, 2);
    ok((await state(page)).debug === 'overdraw', 'F3: the overdraw debug mode');
    await page.keyboard.press('F3');
    await page.keyboard.press('f');
    await frames(page, 1);
    ok((await state(page)).move === 'walk', 'F: walk mode');
    await page.keyboard.press('Tab');
    await frames(page, 1);
    ok((await state(page)).overlay === 0, 'Tab: the overlay off');
    const a0 = (await state(page)).angles;
    await page.mouse.move(320, 240);
    await page.mouse.down();
    await page.mouse.move(420, 260, { steps: 5 });
    await page.mouse.up();
    await frames(page, 2);
    const a1 = (await state(page)).angles;
    ok(Math.abs(a1[1] - a0[1]) > 5 && Math.abs(a1[0] - a0[0]) > 1,
       `the mouse turns the view (angles ${a0} -> ${a1})`);

    /* the screenshot button: a PNG of the frame, encoded by the browser, downloaded */
    const dl = path.join(spec.out, 'downloads');
    fs.mkdirSync(dl, { recursive: true });
    const cdp = await browser.target().createCDPSession();
    await cdp.send('Browser.setDownloadBehavior', { behavior: 'allow', downloadPath: dl });
    await page.evaluate(() => document.exitPointerLock());  /* the drag above may have locked the pointer */
    await page.click('#shot');
    const shot = path.join(dl, 'builtin_web.png');
    for (let i = 0; i < 100 && !fs.existsSync(shot); i++) await new Promise((r) => setTimeout(r, 100));
    const png = fs.existsSync(shot) ? fs.readFileSync(shot) : Buffer.alloc(0);
    const cw = await page.evaluate(() => [document.getElementById('frame').width, document.getElementById('frame').height]);
    ok(png.length > 24 && png.subarray(1, 4).toString() === 'PNG' && png.readUInt32BE(16) === cw[0] &&
       png.readUInt32BE(20) === cw[1], `the screenshot button saves ${shot} (${png.length} bytes, a PNG of ` +
       `${png.length > 24 ? png.readUInt32BE(16) + 'x' + png.readUInt32BE(20) : '?'}, the frame is ${cw.join('x')})`);

    /* resizing the window resizes the frame */
    await page.setViewport({ width: 800, height: 500 });
    await page.waitForFunction(() => window.edgewise.state().width === 800, { timeout: 20000 }).catch(() => {});
    await frames(page, 2);
    const sz = await state(page);
    ok(sz.width === 800 && sz.height === 500, `a window of 800x500 gives a ${sz.width}x${sz.height} frame`);

    /* a map alone, without palette or colormap: the built-in scene's, and a message */
    await upload(page, [spec.lonemap]);
    await frames(page, 2);
    const lone = await state(page), lm = await message(page);
    ok(lone.map === 'e1m1' && /built-in scene's palette/.test(lm), `e1m1.bsp alone: ${lone.map}, "${lm}"`);

    /* a corrupt file: one message on the page, the page keeps drawing */
    const bad = path.join(spec.out, 'broken.bsp');
    fs.writeFileSync(bad, Buffer.from('IBSP this is not a map at all, just some bytes'.repeat(20)));
    const before = await state(page);
    /* dropped on the page, as a person drops it: a drop event with the file */
    const f0 = await page.evaluate(() => window.edgewise.frames), l0 = await page.evaluate(() => window.edgewise.loads);
    await page.evaluate((text) => {
      const dt = new DataTransfer();
      dt.items.add(new File([text], 'broken.bsp'));
      document.getElementById('frame').dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
    }, 'IBSP this is not a map at all, just some bytes'.repeat(20));
    await page.waitForFunction((l) => window.edgewise.loads > l, { timeout: 30000 }, l0);
    await page.waitForFunction((f) => window.edgewise.frames > f + 2, { timeout: 30000 }, f0);
    const m = await message(page), after = await state(page);
    ok(/broken\.bsp/.test(m) && (await page.evaluate(() => document.getElementById('msg').className)) === 'error',
       `a corrupt .bsp gives a message on the page: "${m}"`);
    ok(after.map === before.map, `the page keeps the map it showed (${after.map}) and keeps drawing`);
    const badpak = path.join(spec.out, 'pak0.pak');
    fs.writeFileSync(badpak, Buffer.concat([Buffer.from('PACK'), Buffer.alloc(8, 0xff), Buffer.alloc(100, 7)]));
    await upload(page, [badpak, bad]).catch(() => {});
    await frames(page, 2);
    ok((await message(page)).length > 0 && (await state(page)).map === before.map,
       `a corrupt .pak: "${await message(page)}"`);
    /* the map shown before still has its files: true colour loads it again */
    await page.click('#color');
    await frames(page, 2);
    const again = await state(page);
    ok(again.map === before.map && again.color === 'true', `after the corrupt files, true colour reloads ${again.map} (${again.color})`);
    await page.close();

    /* not cross-origin isolated: one thread, and the page says so */
    const st1 = await open(false, '', 640, 480);
    await frames(st1, 1);
    const m1 = await message(st1);
    ok(/not cross-origin isolated/.test(m1) && (await state(st1)).threads === 1,
       `no COOP/COEP headers: one thread, and the page says so ("${m1}")`);
    await st1.close();

    /* a bad fog= gives a message, and the map is drawn with its own fog */
    const bf = await open(false, 'map=site/maps/lqdm7.bsp&view=0&time=0&fog=0.1,2,0,0', 640, 480);
    await frames(bf, 1);
    const mf = await message(bf);
    ok(/fog must be DENSITY,R,G,B/.test(mf) && (await state(bf)).map === 'lqdm7', `fog=0.1,2,0,0: "${mf}"`);
    await bf.close();

    /* ?bench=1 prints bench's JSON for the view set */
    const bp = await open(true, 'bench=1&map=site/maps/lqdm7.bsp&sizes=640x480&passes=1', 640, 480);
    const rows = await bp.evaluate(() => window.edgewise.bench);
    ok(Array.isArray(rows) && rows.length === 2 && rows.every((r) => r.median_ms > 0 && r.views > 0 && r.map === 'lqdm7') &&
       rows[0].threads === 1,
       'bench=1: ' + JSON.stringify(rows));
    await bp.close();

    /* six processors: six threads from the Web Workers made at start, through
     * a resize and a benchmark (renderers made again, never more workers
     * asked for than the page made) */
    const six = await open(true, 'bench=1&sizes=320x240&passes=1&time=0', 640, 480, 6);
    const rows6 = await six.evaluate(() => window.edgewise.bench);
    await six.setViewport({ width: 700, height: 450 });
    await six.waitForFunction(() => window.edgewise.state().width === 700, { timeout: 30000 }).catch(() => {});
    const s6 = await state(six);
    ok(rows6 && rows6.length === 2 && rows6[1].threads === 6 && s6.threads === 6 && s6.width === 700,
       `six processors: bench threads ${rows6 && rows6.map((r) => r.threads)}, then a ${s6.width}x${s6.height} frame on ${s6.threads} threads`);
    await six.close();
  }
} catch (e) {
  ok(false, 'driving the page: ' + (e.stack || e));
} finally {
  await browser.close();
  servers.true.proc.kill();
  servers.false.proc.kill();
}
process.exit(failed ? 1 : 0);
