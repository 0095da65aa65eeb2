// A real browser as a Foxglove client: Debian's headless Chromium, driven by puppeteer-core, opens a page
// served here on loopback whose script (browser/page.mjs, bundled by esbuild) runs Foxglove's own client,
// @foxglove/ws-protocol's FoxgloveClient, on the browser's own WebSocket, and decodes each message with
// Foxglove's ROS 2 decoder. Prints one JSON line per event: {"browser": VERSION}, {"page": URL}, then the
// page's events (see browser/page.mjs), ending with the close the browser saw.
//
//   node foxglove_browser.mjs URL COUNT TOPIC...   subscribes to TOPICs; closes after COUNT messages on the
//                                                  first TOPIC (and LINGER ms more)
//   node foxglove_browser.mjs URL COUNT            subscribes to every channel; closes after COUNT messages
//
// Environment: CHROMIUM (default: chromium, chromium-browser or google-chrome on PATH), LINGER (ms, 1000),
// DEADLINE (s, 90: the page is told to close then, whatever it has received, and {"deadline": true} printed).
// Start it where the server is reachable (scripts/test's private network namespace); the browser is started
// with its background networking off and reaches nothing but the two loopback servers.
import { createServer } from "node:http";
import { existsSync } from "node:fs";
import { delimiter, join, dirname } from "node:path";
import { fileURLToPath } from "node:url";
import { build } from "esbuild";
import puppeteer from "puppeteer-core";

const here = dirname(fileURLToPath(import.meta.url));
const [url, countArg, ...topics] = process.argv.slice(2);
if (!url || !countArg) {
  console.error("usage: foxglove_browser.mjs URL COUNT [TOPIC...]");
  process.exit(2);
}
const say = (event) => process.stdout.write(JSON.stringify(event) + "\n");

function chromium() {
  if (process.env.CHROMIUM) return process.env.CHROMIUM;
  for (const dir of (process.env.PATH ?? "").split(delimiter)) {
    for (const name of ["chromium", "chromium-browser", "google-chrome"]) {
      if (existsSync(join(dir, name))) return join(dir, name);
    }
  }
  console.error("foxglove_browser.mjs: no chromium on PATH (apt-get install chromium, or set CHROMIUM)");
  process.exit(2);
}

// The page: an HTML shell and the bundled client, served from 127.0.0.1 on a free port.
const bundle = await build({
  entryPoints: [join(here, "browser/page.mjs")],
  bundle: true,
  format: "esm",
  platform: "browser",
  write: false,
  logLevel: "error",
});
const files = {
  "/": ["text/html", '<!doctype html><meta charset="utf-8"><title>sweetspot</title><script type="module" src="/page.js"></script>'],
  "/page.js": ["text/javascript", bundle.outputFiles[0].contents],
};
const server = createServer((req, res) => {
  const file = files[req.url.split("?")[0]];
  if (!file) {
    res.writeHead(404).end();
    return;
  }
  res.writeHead(200, { "content-type": file[0] }).end(file[1]);
});
await new Promise((resolve) => server.listen(0, "127.0.0.1", resolve));
const pageUrl = `http://127.0.0.1:${server.address().port}/`;

const browser = await puppeteer.launch({
  executablePath: chromium(),
  headless: true,
  args: [
    "--no-sandbox", // as root (CI containers); the page is our own
    "--disable-dev-shm-usage",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-default-apps",
    "--disable-sync",
    "--no-first-run",
    "--no-default-browser-check",
  ],
});
let closed;
const done = new Promise((resolve) => (closed = resolve));
try {
  say({ browser: await browser.version() });
  const page = await browser.newPage();
  page.on("pageerror", (error) => say({ error: `page: ${error.message}` }));
  await page.exposeFunction("report", (line) => {
    process.stdout.write(line + "\n");
    if (JSON.parse(line).close !== undefined) closed();
  });
  await page.goto(pageUrl, { waitUntil: "load" });
  say({ page: pageUrl });
  await page.waitForFunction(() => typeof window.sweetspotRun === "function");
  const count = Number(countArg);
  const linger = Number(process.env.LINGER ?? 1000);
  await page.evaluate((options) => (window.run = window.sweetspotRun(options)), { url, topics, count, linger });
  // Bounds only, so that a server that never answers ends the run instead of hanging it.
  const deadline = Number(process.env.DEADLINE ?? 90) * 1000;
  const timer = setTimeout(() => {
    say({ deadline: true });
    page.evaluate(() => window.run.close()).catch(() => {});
    setTimeout(() => closed(), 10_000).unref();
  }, deadline);
  await done;
  clearTimeout(timer);
} finally {
  await browser.close();
  server.close();
}
