// `yarnvox view` in a real browser: Debian's chromium driven by playwright-core
// (tools/setup installs it here with npm ci; no browser is downloaded). A small
// garment is generated and viewed (voxelized by the view) on llvmpipe; the
// page is opened, the camera dragged, and the test checks that frames arrive
// and change with the camera, that the address reopens the same view (the
// same picture), that a mode key switches the render, and that a screenshot
// shows the garment in the middle and background at the corners; then the
// camera zooms in and stops, what it sees is voxelized finer and shown, and,
// saved with the s key, equals `yarnvox voxelize` with the command the view
// gives for that box, value for value (both exported to Mitsuba .vol and
// compared byte for byte). No frame rate is asserted. Fails (never skips) when chromium or node_modules is missing.
//   node tests/browser/view_test.mjs --yarnvox build/yarnvox --scratch DIR
import { spawn, execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const arg = (name) => { const i = process.argv.indexOf(name); return i > 0 ? process.argv[i + 1] : undefined; };
const yarnvox = arg('--yarnvox');
const scratch = arg('--scratch');
const chromiumPath = '/usr/bin/chromium';
let passed = 0, failed = 0;

function check(what, ok, detail = '') {
  if (ok) { passed += 1; console.log('ok: ' + what); }
  else { failed += 1; console.log('FAILED: ' + what + (detail ? ' (' + detail + ')' : '')); }
}

function fatal(why) {
  console.log('FAILED: ' + why);
  console.log(`${passed} passed, ${failed + 1} failed`);
  process.exit(1);
}

if (!yarnvox || !scratch) fatal('usage: view_test.mjs --yarnvox PATH --scratch DIR');
if (!existsSync(chromiumPath)) fatal(chromiumPath + ' is missing: run tools/setup (installs Debian\'s chromium)');
if (!existsSync(join(here, 'node_modules', 'playwright-core')))
  fatal('tests/browser/node_modules is missing: run tools/setup (npm ci in tests/browser; needs the npm registry once)');
const { chromium } = await import('playwright-core');

rmSync(scratch, { recursive: true, force: true });
mkdirSync(scratch, { recursive: true });
const bcc = join(scratch, 'plain.bcc');
execFileSync(yarnvox, ['gen', '--pattern', 'plain', '--crossings', '16', '--quiet', '-o', bcc]);

// The view, on any free port; its address is the line with http://.
const server = spawn(yarnvox, ['view', bcc, '--port', '0', '--resolution', '48', '--size', '320x180', '--save-dir', scratch,
                              '--view-voxels', '96'],
                     { stdio: ['ignore', 'pipe', 'pipe'] });
let serverOut = '';
server.stderr.on('data', (d) => { serverOut += d; });
const url = await new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error('no address within 180 s:\n' + serverOut)), 180000);
  server.stdout.on('data', (d) => {
    serverOut += d;
    const m = /http:\/\/127\.0\.0\.1:\d+\//.exec(serverOut);
    if (m) { clearTimeout(timer); resolve(m[0]); }
  });
  server.on('exit', (code) => reject(new Error('yarnvox view ended (' + code + '):\n' + serverOut)));
}).catch((e) => fatal(e.message));

const browser = await chromium.launch({
  executablePath: chromiumPath, headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking'],
});
try {
  const context = await browser.newContext({ viewport: { width: 640, height: 360 }, deviceScaleFactor: 1 });
  const page = await context.newPage();
  const settled = () => page.waitForFunction(() => window.yvView && window.yvView.settled(), null, { timeout: 180000 });
  // The picture shown, as grey levels of an 80x45 grid (drawn from the <img> into a canvas).
  const picture = (p = page) => p.evaluate(() => {
    const img = document.getElementById('frame');
    const c = document.createElement('canvas');
    c.width = 80; c.height = 45;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0, 80, 45);
    const d = g.getImageData(0, 0, 80, 45).data;
    const out = [];
    for (let i = 0; i < d.length; i += 4) out.push((d[i] + d[i + 1] + d[i + 2]) / 3);
    return out;
  });
  const difference = (a, b) => a.reduce((s, v, i) => s + Math.abs(v - b[i]), 0) / a.length;

  await page.goto(url);
  await settled();
  const first = await page.evaluate(() => ({ frames: window.yvView.frames, hash: location.hash, stats: window.yvView.stats }));
  check('a frame arrives with its stats', first.frames >= 1 && first.stats.bytes > 0 && first.stats.activeVoxels > 0,
        JSON.stringify(first));
  check('the frame has the page\'s size', first.stats.width === 640 && first.stats.height === 360, JSON.stringify(first.stats));
  check('the address holds the camera and mode', /az=30/.test(first.hash) && /mode=raycast/.test(first.hash), first.hash);
  const ruler = await page.evaluate(() => window.yvView.ruler);
  check('a ruler in the garment\'s units, 60 to 150 pixels long',
        ruler && ruler.units === 'world' && ruler.pixels >= 60 && ruler.pixels <= 150 && ruler.length > 0, JSON.stringify(ruler));
  const before = await picture();
  // Voxelize-on-stop off until its own part below: the pictures compared here are of the volume opened.
  await page.keyboard.press('a');
  check('the a key turns voxelize-on-stop off', await page.evaluate(() => window.yvView.autoVoxelize === false));

  // Drag the camera across the middle.
  await page.mouse.move(320, 180);
  await page.mouse.down();
  await page.mouse.move(420, 200, { steps: 8 });
  await page.mouse.up();
  await settled();
  const dragged = await page.evaluate(() => ({ frames: window.yvView.frames, hash: location.hash }));
  const after = await picture();
  check('frames keep arriving while dragging', dragged.frames > first.frames, `${first.frames} then ${dragged.frames}`);
  check('the address follows the camera', dragged.hash !== first.hash && !/az=30&/.test(dragged.hash), dragged.hash);
  check('the picture changes with the camera', difference(before, after) > 2, 'mean difference ' + difference(before, after));
  const motion = await page.evaluate(() => ({ moving: window.yvView.movingFrames, last: window.yvView.stats }));
  check('frames drawn while dragging say the camera moves, the one after it stops does not',
        motion.moving > 0 && motion.last.moving === false && motion.last.degraded === false,
        JSON.stringify({ moving: motion.moving, last: motion.last.moving, degraded: motion.last.degraded }));
  await page.keyboard.press('g');
  await page.waitForFunction(() => window.yvView.stats.degrade === false && window.yvView.settled(), null, { timeout: 180000 });
  const fullQuality = await page.evaluate(() => location.hash);
  await page.keyboard.press('g');
  await page.waitForFunction(() => window.yvView.stats.degrade === true && window.yvView.settled(), null, { timeout: 180000 });
  check('g turns degrading while moving off and on, and the address keeps it',
        /deg=0/.test(fullQuality) && !/deg=0/.test(await page.evaluate(() => location.hash)), fullQuality);

  // The address reopens the same view: the same picture in a fresh page.
  const link = page.url();
  const reopened = await context.newPage();
  await reopened.goto(link);
  await reopened.waitForFunction(() => window.yvView && window.yvView.settled(), null, { timeout: 180000 });
  const again = await picture(reopened);
  check('the link reopens the same view', difference(after, again) < 1, 'mean difference ' + difference(after, again));
  check('the reopened address is the link', reopened.url() === link, reopened.url() + ' vs ' + link);
  await reopened.close();

  // A mode key: 2 is the second mode (mip).
  const modes = await page.evaluate(() => window.yvView.stats && document.getElementById('overlay').textContent);
  await page.keyboard.press('2');
  await page.waitForFunction(() => window.yvView.stats.mode !== 'raycast' && window.yvView.settled(), null, { timeout: 180000 });
  const mode = await page.evaluate(() => ({ mode: window.yvView.stats.mode, hash: location.hash }));
  check('a mode key switches the render and the address', mode.mode === 'mip' && /mode=mip/.test(mode.hash),
        JSON.stringify(mode) + ' ' + modes);
  await page.keyboard.press('1');
  await page.keyboard.press('r');
  await page.keyboard.press('h'); // the help panel off the bottom-left corner
  await page.waitForFunction(() => window.yvView.stats.mode === 'raycast' && window.yvView.settled(), null, { timeout: 180000 });

  // b: the ray cast blended over the slices in one picture (the paper's Figure 3), and back.
  const halves = await picture();
  await page.keyboard.press('b');
  await page.waitForFunction(() => window.yvView.stats.blend === true && window.yvView.settled(), null, { timeout: 180000 });
  const blended = await picture();
  const blendHash = await page.evaluate(() => location.hash);
  check('b blends the ray cast over the slices, and the address keeps it',
        difference(halves, blended) > 2 && /blend=1/.test(blendHash), 'mean difference ' + difference(halves, blended) + ' ' + blendHash);
  await page.keyboard.press('b');
  await page.waitForFunction(() => window.yvView.stats.blend === false && window.yvView.settled(), null, { timeout: 180000 });

  // t: the next transfer function (the ray cast changes, the slices do not); O twice: four times the
  // opacity; ] four times: the fibres lean 0.2 at the yarn's surface (the slices change). The address keeps
  // them and a link restores the same picture; then back to how it was.
  const halfDifference = (a, b, left) => {
    let sum = 0, n = 0;
    for (let i = 0; i < a.length; i += 1) if ((i % 80 < 40) === left) { sum += Math.abs(a[i] - b[i]); n += 1; }
    return sum / n;
  };
  const plainLook = await picture();
  const hiddenAtFirst = await page.evaluate(() => document.getElementById('controls').hidden);
  await page.keyboard.press('c');
  const controls = await page.evaluate(() => ({ hidden: document.getElementById('controls').hidden,
    presets: [...document.getElementById('transfer').options].map((o) => o.value) }));
  await page.keyboard.press('c');
  check('c shows the controls, with the transfer functions, and hides them',
        hiddenAtFirst && !controls.hidden && controls.presets.includes('fibre') && controls.presets.includes('heat') &&
        await page.evaluate(() => document.getElementById('controls').hidden), JSON.stringify(controls));
  await page.keyboard.press('t');
  await page.waitForFunction(() => window.yvView.stats.transfer === 'grey' && window.yvView.settled(), null, { timeout: 180000 });
  const grey = await picture();
  check('t switches the transfer function: the ray cast changes, the slices do not',
        halfDifference(plainLook, grey, false) > 1 && halfDifference(plainLook, grey, true) < 0.5,
        'right ' + halfDifference(plainLook, grey, false) + ', left ' + halfDifference(plainLook, grey, true));
  await page.keyboard.press('O');
  await page.keyboard.press('O');
  await page.waitForFunction(() => window.yvView.stats.opacity === 2 && window.yvView.settled(), null, { timeout: 180000 });
  const denser = await picture();
  check('O raises the opacity', halfDifference(grey, denser, false) > 0.5, 'right ' + halfDifference(grey, denser, false));
  for (let i = 0; i < 4; i += 1) await page.keyboard.press(']');
  await page.waitForFunction(() => window.yvView.stats.twist > 0 && window.yvView.settled(), null, { timeout: 180000 });
  const twisted = await picture();
  const lookHash = await page.evaluate(() => location.hash);
  check('] twists the yarn: the slices change, the ray cast does not',
        halfDifference(denser, twisted, true) > 0.3 && halfDifference(denser, twisted, false) < 0.5,
        'left ' + halfDifference(denser, twisted, true) + ', right ' + halfDifference(denser, twisted, false));
  check('the address keeps the transfer function, opacity and twist',
        /tf=grey/.test(lookHash) && /op=1(&|$)/.test(lookHash) && /tw=0.2(&|$)/.test(lookHash), lookHash);
  const lookPage = await context.newPage();
  await lookPage.goto(page.url());
  await lookPage.waitForFunction(() => window.yvView && window.yvView.settled(), null, { timeout: 180000 });
  const lookAgain = await picture(lookPage);
  check('a link restores the same look', difference(twisted, lookAgain) < 1, 'mean difference ' + difference(twisted, lookAgain));
  await lookPage.close();
  await page.keyboard.press('t');
  await page.keyboard.press('t');
  await page.keyboard.press('o');
  await page.keyboard.press('o');
  for (let i = 0; i < 4; i += 1) await page.keyboard.press('[');
  await page.waitForFunction(() => window.yvView.stats.transfer === 'fibre' && window.yvView.stats.opacity === 1 &&
                                   window.yvView.stats.twist === 0 && window.yvView.settled(), null, { timeout: 180000 });
  check('and back to how it was', difference(plainLook, await picture()) < 1);

  // p: a screenshot at twice the frame's size, sent once and saved by the browser, never shown in the view.
  const download = page.waitForEvent('download', { timeout: 180000 }).catch(() => null);
  await page.keyboard.press('p');
  await page.waitForFunction(() => window.yvView.screenshot, null, { timeout: 180000 });
  const shot = await page.evaluate(() => ({ shot: window.yvView.screenshot, size: window.yvView.size }));
  check('p takes a screenshot at twice the frame\'s size', shot.shot.width === 2 * shot.size[0] &&
        shot.shot.height === 2 * shot.size[1] && shot.shot.bytes > 1000, JSON.stringify(shot));
  const downloaded = await download;
  check('the browser is handed it as a download', downloaded !== null && /yarnvox-view-\d+x\d+\.jpg/.test(downloaded.suggestedFilename()),
        downloaded ? downloaded.suggestedFilename() : 'no download');
  await page.waitForFunction(() => window.yvView.settled(), null, { timeout: 180000 });

  // A screenshot of the page: the garment near the centre of each half (slices left, ray cast right),
  // background at the corners the overlay does not cover.
  const png = await page.screenshot();
  const regions = await page.evaluate(async (b64) => {
    const img = new Image();
    img.src = 'data:image/png;base64,' + b64;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const lit = (x0, y0, w, h) => {
      const d = g.getImageData(x0, y0, w, h).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) n += d[i] + d[i + 1] + d[i + 2] > 60 ? 1 : 0;
      return n / (w * h);
    };
    const W = img.width, H = img.height;
    return {
      leftCentre: lit(W / 4 - 40, H / 2 - 30, 80, 60), rightCentre: lit((3 * W) / 4 - 40, H / 2 - 30, 80, 60),
      topRight: lit(W - 16, 0, 16, 16), bottomRight: lit(W - 16, H - 16, 16, 16), bottomLeft: lit(0, H - 16, 16, 16),
    };
  }, png.toString('base64'));
  check('the screenshot shows the slices near the centre of the left half', regions.leftCentre > 0.2, JSON.stringify(regions));
  check('the screenshot shows the ray cast near the centre of the right half', regions.rightCentre > 0.2, JSON.stringify(regions));
  check('the corners are background', regions.topRight === 0 && regions.bottomRight === 0 && regions.bottomLeft === 0,
        JSON.stringify(regions));

  // Voxelize what the camera sees: on again, zoom in with the wheel and stop; the view's run is shown.
  await page.keyboard.press('a');
  await page.mouse.move(480, 180);
  await page.mouse.wheel(0, -1200);
  await page.waitForFunction(() => window.yvView.stats && window.yvView.stats.detail && window.yvView.stats.detail.shown &&
                                   window.yvView.stats.detail.final && window.yvView.settled(), null, { timeout: 300000 });
  const shown = await page.evaluate(() => ({ stats: window.yvView.stats, voxelize: window.yvView.voxelize,
                                             hello: null, ms: window.yvView.stopToDetailMs }));
  const detail = shown.stats.detail;
  check('the camera stopping asked for its view to be voxelized',
        shown.voxelize.some((m) => m.state === 'asked') && shown.voxelize.some((m) => m.state === 'running'),
        JSON.stringify(shown.voxelize));
  check('the view\'s run is shown, and timed from the stop', detail.activeVoxels > 0 && shown.ms > 0, JSON.stringify(detail));
  await page.keyboard.press('s');
  await page.waitForFunction(() => window.yvView.voxelize.some((m) => m.state === 'saved' || m.state === 'failed'),
                             null, { timeout: 180000 });
  const saved = await page.evaluate(() => window.yvView.voxelize.find((m) => m.state === 'saved' || m.state === 'failed'));
  check('the s key saves the view\'s run as a .vdb', saved.state === 'saved' && existsSync(saved.vdb), JSON.stringify(saved));
  if (saved.state === 'saved') {
    const cli = join(scratch, 'cli.vdb');
    execFileSync(yarnvox, [...detail.command, '--quiet', '-o', cli]);
    for (const [vdb, vol] of [[saved.vdb, join(scratch, 'view.vol')], [cli, join(scratch, 'cli.vol')]])
      execFileSync(yarnvox, ['export', vdb, '-o', vol, '--quiet']);
    const same = (a, b) => existsSync(a) && existsSync(b) && readFileSync(a).equals(readFileSync(b));
    check('the saved run equals yarnvox voxelize of the same box, density value for value',
          same(join(scratch, 'view.vol'), join(scratch, 'cli.vol')), detail.command.join(' '));
    check('and fibre orientation value for value',
          same(join(scratch, 'view.orientation.vol'), join(scratch, 'cli.orientation.vol')), detail.command.join(' '));
  }
} catch (e) {
  check('the browser session', false, e.stack);
} finally {
  await browser.close();
}

server.kill('SIGTERM');
const code = await new Promise((resolve) => server.on('exit', (c) => resolve(c)));
check('yarnvox view stops cleanly on SIGTERM', code === 0 && /stopped by SIGTERM/.test(serverOut), 'exit ' + code + '\n' + serverOut);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
