// The scripted viewer check (run by ctest as cli.view_script_readout): replays a viewer script
// under Xvfb that flies to the radar by name, grab-drags, zooms, tilts, steps time, flies to the
// storm and moves the pointer over it, then
//  1. the `readout:` line (site, field, value, sweep, azimuth, range) must agree with
//     `atmoglobe gates` of the volume shown: the gate named by sweep, azimuth and range is one
//     row of `gates`, with an echo, and the readout's value is that row's value;
//  2. the screenshot must show the panel: the same script without the panel (--no-panel) gives a
//     picture that differs inside the panel's box and matches outside it.
// Usage: node view_script_check.js XVFB_RUN ATMOGLOBE RADAR_LOOP_DIR SCRIPT OUT_DIR
'use strict';
const { execFileSync } = require('child_process');
const fs = require('fs');
const zlib = require('zlib');
const path = require('path');

const [xvfb, ag, loopDir, script, outDir] = process.argv.slice(2);
function fail(msg) {
  console.error('FAIL: ' + msg);
  process.exit(1);
}
function run(cmd, args, options = {}) {
  try {
    return execFileSync(cmd, args, { encoding: 'utf8', maxBuffer: 1 << 30, ...options });
  } catch (e) {
    fail(`${cmd} ${args.join(' ')} exited ${e.status}:\n${e.stdout}\n${e.stderr}`);
  }
}
function view(extra, shot) {
  return run(xvfb, ['-a', '-s', '-screen 0 1280x800x24', ag, 'view', '--radar', loopDir, '--size', '1000x700',
                    '--script', script, '--screenshot', shot, ...extra]);
}

// PNG (8-bit RGB/RGBA, not interlaced) to {width, height, channels, data}.
function readPng(file) {
  const buf = fs.readFileSync(file);
  let pos = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (pos < buf.length) {
    const len = buf.readUInt32BE(pos), type = buf.toString('ascii', pos + 4, pos + 8);
    const body = buf.subarray(pos + 8, pos + 8 + len);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || body[12] !== 0) fail(`${file}: only 8-bit non-interlaced PNGs are read here`);
      channels = { 2: 3, 6: 4 }[body[9]];
      if (!channels) fail(`${file}: colour type ${body[9]} not read here`);
    } else if (type === 'IDAT') {
      idat.push(body);
    }
    pos += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels, data = Buffer.alloc(stride * height);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    for (let x = 0; x < stride; ++x) {
      const v = raw[y * (stride + 1) + 1 + x];
      const a = x >= channels ? data[y * stride + x - channels] : 0;
      const b = y > 0 ? data[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? data[(y - 1) * stride + x - channels] : 0;
      let p = 0;
      if (filter === 1) p = a;
      else if (filter === 2) p = b;
      else if (filter === 3) p = (a + b) >> 1;
      else if (filter === 4) {
        const pa = Math.abs(b - c), pb = Math.abs(a - c), pc = Math.abs(a + b - 2 * c);
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      data[y * stride + x] = (v + p) & 255;
    }
  }
  return { width, height, channels, data };
}

const shot = path.join(outDir, 'view_script.png');
const out = view([], shot);
fs.writeFileSync(path.join(outDir, 'view_script_stdout.txt'), out);
console.log(out);

// The time shown (the script steps from the newest volume back to the oldest, looping).
const times = [...out.matchAll(/^time: (\S+)/gm)].map((m) => m[1]);
if (times.length < 2) fail('expected the script to step time (time: lines)');
const shownTime = times[times.length - 1];
const readouts = [...out.matchAll(/^readout: (\S+) (\S+): (-?[0-9.]+) \S+ +\(sweep (-?[0-9.]+) deg, azimuth ([0-9.]+) deg, range ([0-9.]+) km/gm)];
if (readouts.length === 0) fail('no radar readout line (readout: SITE FIELD: VALUE ...) in the output');
const r = readouts[readouts.length - 1];
const [site, field, value, sweepDeg, azimuthDeg, rangeKm] = [r[1], r[2], +r[3], +r[4], +r[5], +r[6]];
console.log(`readout: ${site} ${field} ${value} at sweep ${sweepDeg} az ${azimuthDeg} range ${rangeKm} km (time ${shownTime})`);

// The volume of that time, and its sweeps.
const files = fs.readdirSync(loopDir).map((f) => path.join(loopDir, f));
const infos = files.map((f) => [f, JSON.parse(run(ag, ['info', f, '--json']))]);
const shown = infos.find(([, info]) => info.time === shownTime);
if (!shown) fail(`no volume in ${loopDir} has the time shown, ${shownTime}`);
const [file, info] = shown;
if (info.site.name !== site) fail(`readout site ${site} is not the file's ${info.site.name}`);
const sweeps = info.sweeps.map((s) => s.fixed_angle_deg);
let nearest = 0;
sweeps.forEach((e, i) => { if (Math.abs(e - sweepDeg) < Math.abs(sweeps[nearest] - sweepDeg)) nearest = i; });
// The readout prints the elevation with 2 decimals.
if (Math.abs(sweeps[nearest] - sweepDeg) > 0.006) fail(`readout sweep ${sweepDeg} deg is no sweep of ${file}`);

function gatesAround(k) {
  const csv = run(ag, ['gates', file, '--field', field, '--sweep', String(k)], { stdio: ['ignore', 'pipe', 'ignore'] });
  const rows = [];
  for (const line of csv.split('\n').slice(1)) {
    if (!line) continue;
    const c = line.split(',');
    const az = +c[3], range = +c[5] / 1000;
    let dAz = Math.abs(az - azimuthDeg);
    dAz = Math.min(dAz, 360 - dAz);
    if (dAz <= 1.01 && Math.abs(range - rangeKm) <= 0.26) rows.push({ az, range, dAz, value: c[12] === '' ? NaN : +c[12], line });
  }
  return rows;
}
const here = gatesAround(nearest);
// The readout reads one gate as stored (nearest-neighbour) and prints its ray azimuth with 1
// decimal and its range in km with 3 (to the metre), so exactly one row of `gates` must match:
// azimuth within the 0.05 deg print rounding, range within 0.5 m, and the value within the 0.05
// print rounding of one decimal.
const gate = here.filter((g) => g.dAz <= 0.05 + 1e-9 && Math.abs(g.range - rangeKm) <= 0.0005);
if (gate.length !== 1) fail(`${gate.length} gates of sweep ${nearest} at azimuth ${azimuthDeg}, range ${rangeKm} km (expected 1)`);
console.log('gate read: ' + gate[0].line);
if (!Number.isFinite(gate[0].value)) fail(`the gate read has no echo in gates: ${gate[0].line}`);
if (Math.abs(gate[0].value - value) > 0.05 + 1e-9) fail(`readout ${value} is not the gate's value ${gate[0].value}`);
console.log(`readout value ${value} = the gate's ${gate[0].value}`);

// The panel: the same script without it must differ inside the panel's box, and not elsewhere.
const noPanelShot = path.join(outDir, 'view_script_no_panel.png');
view(['--no-panel'], noPanelShot);
const a = readPng(shot), b = readPng(noPanelShot);
if (a.width !== b.width || a.height !== b.height) fail('screenshots differ in size');
function meanDiff(x0, y0, x1, y1) {
  let sum = 0, n = 0;
  for (let y = y0; y < y1; ++y)
    for (let x = x0; x < x1; ++x)
      for (let ch = 0; ch < 3; ++ch) {
        sum += Math.abs(a.data[(y * a.width + x) * a.channels + ch] - b.data[(y * b.width + x) * b.channels + ch]);
        ++n;
      }
  return sum / n;
}
// The panel sits at the top left (10, 10) and is wider than 250 px and taller than 150 px; the
// middle of the bottom half is free of the panel and of the fly-to box (bottom right).
const inPanel = meanDiff(15, 15, 250, 150);
const outside = meanDiff(Math.floor(a.width * 0.3), Math.floor(a.height * 0.55), Math.floor(a.width * 0.6), a.height - 5);
console.log(`mean |difference| with and without the panel: ${inPanel.toFixed(1)} inside its box, ${outside.toFixed(2)} outside`);
// Inside: the panel's dark background and text over the globe differ by tens of levels; outside
// the pictures are the same renders (1 level allows for nothing; they are deterministic).
if (!(inPanel > 20)) fail('the screenshot does not show the panel');
if (!(outside < 1)) fail('the pictures differ outside the panel');
console.log('OK');
