#!/usr/bin/env node
/*
 * serve.mjs - serves the web page (make web-serve; docs/web.md) on
 * localhost with the headers that make it cross-origin isolated
 * (Cross-Origin-Opener-Policy: same-origin, Cross-Origin-Embedder-Policy:
 * require-corp), so the renderer's threads can share memory.
 *
 *   node serve.mjs [--root DIR] [--port N] [--mount /PREFIX=DIR]... [--no-isolation]
 *
 * --root: the folder served (default: this script's own folder, the page);
 * --mount: another folder under a URL prefix (e.g. /data=../shared/data/librequake,
 * then ?map=data/maps/lqdm7.bsp); --no-isolation leaves the two headers out
 * (the page then runs on one thread and says so).  --port 0 picks a free
 * port; the first line printed is "serving http://127.0.0.1:PORT/".
 */
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const args = process.argv.slice(2);
let root = path.dirname(fileURLToPath(import.meta.url));
let port = 8080, isolation = true;
const mounts = [];
for (let i = 0; i < args.length; i++) {
  const a = args[i];
  if (a === '--root') root = args[++i];
  else if (a === '--port') port = parseInt(args[++i], 10);
  else if (a === '--mount') {
    const m = /^(\/[^=]*)=(.+)$/.exec(args[++i] || '');
    if (!m) { console.error('serve.mjs: --mount /PREFIX=DIR'); process.exit(2); }
    mounts.push([m[1].replace(/\/+$/, ''), path.resolve(m[2])]);
  } else if (a === '--no-isolation') isolation = false;
  else { console.error('usage: node serve.mjs [--root DIR] [--port N] [--mount /PREFIX=DIR]... [--no-isolation]'); process.exit(2); }
}
root = path.resolve(root);
const types = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript',
                '.wasm': 'application/wasm', '.png': 'image/png', '.json': 'application/json' };

const server = http.createServer((req, res) => {
  let url;
  try { url = new URL(req.url, 'http://localhost'); } catch { res.writeHead(400).end(); return; }
  let rel = decodeURIComponent(url.pathname);
  let base = root;
  for (const [prefix, dir] of mounts)
    if (rel === prefix || rel.startsWith(prefix + '/')) { base = dir; rel = rel.slice(prefix.length); break; }
  if (rel.endsWith('/')) rel += 'index.html';
  const file = path.join(base, path.normalize('/' + rel));
  if (!file.startsWith(base + path.sep) && file !== base) { res.writeHead(403).end(); return; }
  const headers = { 'Cache-Control': 'no-cache', 'Cross-Origin-Resource-Policy': 'same-origin' };
  if (isolation) {
    headers['Cross-Origin-Opener-Policy'] = 'same-origin';
    headers['Cross-Origin-Embedder-Policy'] = 'require-corp';
  }
  fs.stat(file, (err, st) => {
    if (err || !st.isFile()) { res.writeHead(404, headers).end('not found\n'); return; }
    headers['Content-Type'] = types[path.extname(file).toLowerCase()] || 'application/octet-stream';
    headers['Content-Length'] = st.size;
    res.writeHead(200, headers);
    if (req.method === 'HEAD') { res.end(); return; }
    fs.createReadStream(file).pipe(res);
  });
});
server.listen(port, '127.0.0.1', () => {
  console.log(`serving http://127.0.0.1:${server.address().port}/ (${root}${isolation ? ', cross-origin isolated' : ', not isolated'})`);
});
