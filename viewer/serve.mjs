#!/usr/bin/env node
// A small static server (node built-ins only) for the viewer, bound to 127.0.0.1:
//   /                  the page (index.html), /viewer.js, /lib/*.js
//   /three/...         node_modules/three (no CDN)
//   /results/...       the result folder
//   /tasks.json        the task folders of the result folder (each holds a task.json)
// Nothing outside these folders is served: '..' segments, encoded or not, NUL bytes and symbolic
// links leading outside are refused (403); folders are not listed.
//
//   usage: node viewer/serve.mjs RESULTS_DIR [--port N]     (default port 8765; 0: any free port)
import http from 'node:http';
import fs from 'node:fs';
import fsp from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const VIEWER_DIR = path.dirname(fileURLToPath(import.meta.url));
export const THREE_DIR = path.join(VIEWER_DIR, 'node_modules', 'three');

const MIME = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8', '.json': 'application/json; charset=utf-8',
  '.css': 'text/css; charset=utf-8', '.png': 'image/png', '.svg': 'image/svg+xml',
  '.txt': 'text/plain; charset=utf-8', '.md': 'text/plain; charset=utf-8', '.csv': 'text/csv; charset=utf-8',
  '.ply': 'application/octet-stream', '.off': 'text/plain; charset=utf-8',
};

/**
 * The absolute path of `relative` (a URL path, still percent-encoded) inside `root`, or null when
 * it is malformed or would leave `root` (does not look at the file system; see realInside).
 */
export function resolveInside(root, relative) {
  let decoded;
  try { decoded = decodeURIComponent(relative); } catch { return null; }
  if(decoded.includes('\0')) return null;
  const segments = decoded.split(/[/\\]+/).filter((s) => s !== '' && s !== '.');
  if(segments.some((s) => s === '..' || path.isAbsolute(s) || /^[a-zA-Z]:/.test(s))) return null;
  const base = path.resolve(root);
  const full = path.resolve(base, ...segments);
  return full === base || full.startsWith(base + path.sep) ? full : null;
}

/** True when the real path of `full` (symbolic links resolved) is inside the real path of `root`. */
async function realInside(root, full) {
  const [realRoot, realFull] = await Promise.all([fsp.realpath(root), fsp.realpath(full)]);
  return realFull === realRoot || realFull.startsWith(realRoot + path.sep);
}

/** The task folders of a result folder: [{ dir, task, title, panels } or { dir, task, error }]. */
export async function listTasks(resultsDir) {
  const read = async (dir) => {
    const file = path.join(resultsDir, dir, 'task.json');
    try { await fsp.access(file); } catch { return null; }
    try {
      const json = JSON.parse(await fsp.readFile(file, 'utf8'));
      const name = typeof json.task === 'string' && json.task ? json.task :
        (dir === '.' ? path.basename(path.resolve(resultsDir)) : dir);
      return { dir, task: name, title: typeof json.title === 'string' ? json.title : '',
               panels: Array.isArray(json.panels) ? json.panels : null };
    } catch(e) {
      return { dir, task: dir, error: `cannot read task.json: ${e.message}` };
    }
  };
  const tasks = [];
  const top = await read('.');
  if(top) tasks.push(top);
  const entries = await fsp.readdir(resultsDir, { withFileTypes: true });
  for(const entry of entries.filter((e) => e.isDirectory()).sort((a, b) => a.name.localeCompare(b.name))) {
    const task = await read(entry.name);
    if(task) tasks.push(task);
  }
  return tasks;
}

function send(res, status, body, type = 'text/plain; charset=utf-8') {
  res.writeHead(status, { 'Content-Type': type, 'Cache-Control': 'no-store', 'X-Content-Type-Options': 'nosniff' });
  res.end(body);
}

async function sendFile(req, res, root, relative) {
  const full = resolveInside(root, relative);
  if(!full) return send(res, 403, 'forbidden\n');
  let stat;
  try {
    if(!(await realInside(root, full))) return send(res, 403, 'forbidden\n');
    stat = await fsp.stat(full);
  } catch {
    return send(res, 404, 'not found\n');
  }
  if(!stat.isFile()) return send(res, 404, 'not found\n');
  res.writeHead(200, {
    'Content-Type': MIME[path.extname(full).toLowerCase()] || 'application/octet-stream',
    'Content-Length': stat.size, 'Cache-Control': 'no-store', 'X-Content-Type-Options': 'nosniff',
  });
  if(req.method === 'HEAD') return res.end();
  fs.createReadStream(full).on('error', () => res.destroy()).pipe(res);
}

/** The request handler for a result folder. */
export function createHandler(resultsDir) {
  const results = path.resolve(resultsDir);
  const pageFiles = new Set(['index.html', 'viewer.js']);
  return async (req, res) => {
    try {
      if(req.method !== 'GET' && req.method !== 'HEAD') return send(res, 405, 'method not allowed\n');
      // The raw path (no URL normalisation: the guards see exactly what was sent).
      const rawPath = (req.url || '/').split(/[?#]/)[0];
      if(!rawPath.startsWith('/')) return send(res, 400, 'bad request\n');
      if(rawPath === '/') return sendFile(req, res, VIEWER_DIR, 'index.html');
      if(rawPath === '/tasks.json')
        return send(res, 200, JSON.stringify(await listTasks(results)), MIME['.json']);
      const mounts = [['/lib/', path.join(VIEWER_DIR, 'lib')], ['/three/', THREE_DIR], ['/results/', results]];
      for(const [prefix, root] of mounts)
        if(rawPath.startsWith(prefix)) return sendFile(req, res, root, rawPath.slice(prefix.length));
      const name = rawPath.slice(1);
      if(pageFiles.has(name)) return sendFile(req, res, VIEWER_DIR, name);
      return send(res, 404, 'not found\n');
    } catch(e) {
      if(!res.headersSent) send(res, 500, `internal error: ${e.message}\n`);
      else res.destroy();
    }
  };
}

/**
 * Starts the server on 127.0.0.1. Resolves to { server, url, port, close() }.
 * Fails when the result folder or node_modules/three is missing.
 */
export async function startServer(resultsDir, { port = 0, host = '127.0.0.1' } = {}) {
  const stat = await fsp.stat(resultsDir).catch(() => null);
  if(!stat || !stat.isDirectory()) throw new Error(`result folder '${resultsDir}' does not exist or is not a folder`);
  if(!fs.existsSync(path.join(THREE_DIR, 'build', 'three.module.js')))
    throw new Error(`three.js is not installed in ${THREE_DIR}: run 'npm ci' in ${VIEWER_DIR}`);
  const server = http.createServer(createHandler(resultsDir));
  await new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => { server.off('error', reject); resolve(); });
  });
  const actual = server.address().port;
  return {
    server, port: actual, url: `http://${host}:${actual}/`,
    close: () => new Promise((resolve) => { server.closeAllConnections?.(); server.close(() => resolve()); }),
  };
}

async function main(argv) {
  const args = argv.slice(2);
  let port = 8765, portGiven = false, dir = null;
  for(let i = 0; i < args.length; ++i) {
    if(args[i] === '--port') {
      port = Number(args[++i]); portGiven = true;
      if(!Number.isInteger(port) || port < 0 || port > 65535) throw new Error(`bad port '${args[i]}'`);
    } else if(args[i] === '--help' || args[i] === '-h') {
      console.log('usage: node viewer/serve.mjs RESULTS_DIR [--port N]   (N = 0: any free port)');
      return;
    } else if(dir === null) dir = args[i];
    else throw new Error(`unexpected argument '${args[i]}'`);
  }
  if(dir === null) throw new Error('usage: node viewer/serve.mjs RESULTS_DIR [--port N]');
  let handle;
  try {
    handle = await startServer(dir, { port });
  } catch(e) {
    if(e.code !== 'EADDRINUSE' || portGiven) throw e;
    handle = await startServer(dir, { port: 0 });      // the default port is taken: any free one
  }
  const tasks = await listTasks(path.resolve(dir));
  console.log(`Serving ${path.resolve(dir)} (${tasks.length} task${tasks.length === 1 ? '' : 's'})`);
  console.log(`Open ${handle.url}   (Ctrl-C stops)`);
  const stop = () => handle.close().then(() => process.exit(0));
  process.on('SIGINT', stop);
  process.on('SIGTERM', stop);
}

if(process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url))
  main(process.argv).catch((e) => { console.error(`serve.mjs: ${e.message}`); process.exit(2); });
