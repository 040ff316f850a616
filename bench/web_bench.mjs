#!/usr/bin/env node
/*
 * web_bench.mjs - the figures of docs/web.md: the page's ?bench=1 (the
 * benchmark protocol of `edgewise bench`: the view set once untimed, then
 * PASSES timed passes) in headless chromium against the native command on
 * the same machine, the same maps, views and sizes; the .wasm sizes; the
 * time from asking for the page to its first frame.
 *
 *   node bench/web_bench.mjs [--maps lqdm7,e1m1] [--sizes 640x480,1920x1080] [--passes 5] [--color true] [--page st]
 *   (--page st: the page that is not cross-origin isolated, the one-thread build: one thread only)
 *   node bench/web_bench.mjs --shot FILE.png [--shotq QUERY]   (docs/web-lqdm7.png: the default query)
 *
 * Needs make web (build-web/web), make build (build/edgewise), chromium and
 * tests/web/node_modules (npm ci there).  Prints one JSON line per row
 * ("web" or "native", map, size, threads, median_ms, mean_ms) and a table.
 */
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { spawn, execFileSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const { default: puppeteer } = await import(path.join(root, 'tests/web/node_modules/puppeteer-core/lib/esm/puppeteer/puppeteer-core.js'));
const opt = { maps: 'lqdm7,e1m1', sizes: '640x480,1920x1080', passes: '5', data: path.join(root, '../shared/data/librequake'),
              color: '8bit', page: 'iso', web: path.join(root, 'build-web/web'), cli: path.join(root, 'build/edgewise'), chromium: '/usr/bin/chromium' };
for (let i = 2; i < process.argv.length; i += 2) opt[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];

function serve(isolated) {
  return new Promise((resolve, reject) => {
    const args = [path.join(opt.web, 'serve.mjs'), '--root', opt.web, '--port', '0', '--mount', '/data=' + opt.data];
    if (!isolated) args.push('--no-isolation');
    const p = spawn(process.execPath, args, { stdio: ['ignore', 'pipe', 'inherit'] });
    p.stdout.once('data', (d) => resolve({ proc: p, url: /http:\/\/[^ ]+\//.exec(String(d))[0] }));
    p.on('error', reject);
  });
}

/* sizes */
for (const f of ['edgewise.wasm', 'edgewise-st.wasm', 'edgewise.js', 'edgewise-st.js', 'edgewise.worker.js', 'page.js', 'index.html']) {
  const b = fs.readFileSync(path.join(opt.web, f));
  console.log(JSON.stringify({ file: f, bytes: b.length, gzip_bytes: zlib.gzipSync(b, { level: 9 }).length }));
}

const servers = { iso: await serve(true), st: await serve(false) };
if (opt.shot) {  /* --shot FILE [--shotq QUERY]: a picture of the page (docs/web-lqdm7.png) */
  const b = await puppeteer.launch({ executablePath: opt.chromium, headless: true,
                                     args: ['--no-sandbox', '--disable-gpu', '--hide-scrollbars'] });
  const page = await b.newPage();
  await page.setViewport({ width: 800, height: 500 });
  await page.goto(servers.iso.url + 'index.html?' + (opt.shotq || 'map=data/maps/lqdm7.bsp&color=true&pos=48,-16,-18&angles=0,15,0&embed=0'));
  await page.evaluate(() => window.edgewise.ready);
  await page.waitForFunction(() => window.edgewise.frames > 30, { timeout: 60000 });
  await page.screenshot({ path: opt.shot });
  console.log('wrote ' + opt.shot + ': ' + JSON.stringify(await page.evaluate(() => window.edgewise.state())));
  await b.close();
  servers.iso.proc.kill();
  servers.st.proc.kill();
  process.exit(0);
}
const browser = await puppeteer.launch({ executablePath: opt.chromium, headless: true,
                                         args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'] });
const rows = [];
try {
  /* first frame: a fresh page each time (the files come from localhost) */
  for (const [kind, q] of [['builtin', ''], ['lqdm7', 'map=data/maps/lqdm7.bsp&color=true']]) {
    for (const s of ['iso', 'st']) {
      const times = [];
      for (let k = 0; k < 3; k++) {
        const page = await browser.newPage();
        await page.setViewport({ width: 640, height: 480 });
        await page.goto(servers[s].url + 'index.html?' + q);
        await page.evaluate(() => window.edgewise.ready);
        await page.waitForFunction(() => window.edgewise.firstFrameMs !== null);
        times.push(await page.evaluate(() => window.edgewise.firstFrameMs));
        await page.close();
      }
      times.sort((a, b) => a - b);
      console.log(JSON.stringify({ first_frame: kind, page: s === 'iso' ? 'threads' : 'one thread', ms: times.map((t) => +t.toFixed(1)), median_ms: +times[1].toFixed(1) }));
    }
  }
  for (const map of opt.maps.split(',')) {
    const page = await browser.newPage();
    page.on('console', (m) => { if (/^\{/.test(m.text())) { const r = JSON.parse(m.text()); r.kind = 'web'; rows.push(r); console.log(JSON.stringify(r)); } });
    await page.setViewport({ width: 640, height: 480 });
    await page.goto(servers[opt.page === 'st' ? 'st' : 'iso'].url + `index.html?bench=1&map=data/maps/${map}.bsp&sizes=${opt.sizes}&passes=${opt.passes}` +
                    (opt.color === 'true' ? '&color=true' : ''));
    await page.evaluate(() => window.edgewise.ready);
    await page.close();
    const args = ['bench', map, '--data', opt.data, '--passes', opt.passes, '--threads', '1', '--threads', '0', '--color', opt.color];
    for (const s of opt.sizes.split(',')) args.push('--size', s);
    const out = execFileSync(opt.cli, args, { encoding: 'utf8' });
    for (const line of out.split('\n').filter((l) => l.startsWith('{'))) {
      const r = JSON.parse(line);
      r.kind = 'native';
      rows.push(r);
      console.log(JSON.stringify({ kind: 'native', map: r.map, width: r.width, height: r.height, threads: r.threads,
                                   views: r.views, median_ms: r.median_ms, mean_ms: r.mean_ms }));
    }
  }
} finally {
  await browser.close();
  servers.iso.proc.kill();
  servers.st.proc.kill();
}
console.log('\n| map | size | threads | views | native median / mean ms | web median / mean ms | web / native (median) |');
console.log('|---|---|---:|---:|---:|---:|---:|');
for (const w of rows.filter((r) => r.kind === 'web')) {
  const n = rows.find((r) => r.kind === 'native' && r.map === w.map && r.width === w.width && r.height === w.height &&
                      (w.threads_requested === 1 ? r.threads === 1 : r.threads !== 1));
  if (!n) continue;
  console.log(`| ${w.map} | ${w.width}x${w.height} | ${w.threads} | ${w.views} | ${n.median_ms.toFixed(2)} / ${n.mean_ms.toFixed(2)} | ` +
              `${w.median_ms.toFixed(2)} / ${w.mean_ms.toFixed(2)} | ${(w.median_ms / n.median_ms).toFixed(2)}x |`);
}
