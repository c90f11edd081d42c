// A hostile site for dashboard.spec.mjs: pages served from another port of the
// dashboard's host (so the same site, another origin) that post a text/plain form to the
// dashboard, the one kind of cross-origin request a page can make with the browser's
// cookie and a body of its choosing without a CORS preflight.

import http from 'node:http';

const escapeAttr = (s) => s.replace(/&/g, '&amp;').replace(/"/g, '&quot;').replace(/</g, '&lt;');

// The form's one field is named so that the text/plain body "NAME=VALUE\r\n" is the
// JSON the attacker wants: NAME is the object's JSON up to the opening quote of the
// string field pad, which the "=" and VALUE ('"}') close. pad must be a field the
// endpoint takes as any string (the scene's name), or ignores (the login's extra fields).
function formPage(action, object, pad) {
  const { [pad]: _, ...rest } = object;
  const json = JSON.stringify(rest);
  const name = `${json.slice(0, -1)}${json === '{}' ? '' : ','}"${pad}":"`;
  return `<!doctype html><html><body>
<form id="f" method="POST" enctype="text/plain" action="${escapeAttr(action)}">
<input type="hidden" name="${escapeAttr(name)}" value="${escapeAttr('"}')}">
</form>
<script>document.getElementById('f').submit();</script>
</body></html>`;
}

/**
 * Serves /login (posts {"token": token} to the dashboard's login) and /submit (posts
 * sceneJSON to its jobs) on 127.0.0.1 at a free port. Resolves to { origin, close }.
 */
export function startCrossOriginSite(dashboardURL, token, sceneJSON) {
  const pages = {
    '/login': formPage(new URL('api/login', dashboardURL).toString(), { token }, 'pad'),
    '/submit': formPage(new URL('api/jobs', dashboardURL).toString(), JSON.parse(sceneJSON), 'name'),
  };
  const server = http.createServer((req, res) => {
    const page = pages[req.url];
    res.writeHead(page ? 200 : 404, { 'content-type': 'text/html; charset=utf-8' });
    res.end(page ?? 'no such page');
  });
  return new Promise((resolve) => {
    server.listen(0, '127.0.0.1', () => {
      resolve({ origin: `http://127.0.0.1:${server.address().port}`, close: () => server.close() });
    });
  });
}
