// A static file server on 127.0.0.1 for the browser tests: the folder as a web server would serve
// it (the content types a browser needs for modules and WebAssembly), on a free port.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';

const TYPES = { '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.wasm': 'application/wasm',
  '.css': 'text/css', '.json': 'application/json', '.sscape': 'application/octet-stream', '.ts': 'text/plain' };

/** Serves `root`; resolves to { url, close() }. */
export function serve(root) {
  const base = path.resolve(root);
  const server = http.createServer((request, response) => {
    const local = path.normalize(path.join(base, decodeURIComponent(new URL(request.url, 'http://x').pathname)));
    const file = local.endsWith(path.sep) ? path.join(local, 'index.html') : local;
    if (!file.startsWith(base) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      response.writeHead(404).end('not found');
      return;
    }
    response.writeHead(200, { 'content-type': TYPES[path.extname(file)] ?? 'application/octet-stream' });
    fs.createReadStream(file).pipe(response);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve({
    url: `http://127.0.0.1:${server.address().port}/`,
    close: () => new Promise((done) => { server.closeAllConnections(); server.close(done); }),
  })));
}
