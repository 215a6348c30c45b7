// A quick check of an engine adapter (docs/protocol.md), for adapter authors:
//   node check.mjs NAME.json            (a registration file: its command is run)
//   node check.mjs node rapier.mjs --config default
//   node check.mjs --set iterations=50 cannon.json      (knob values for the car)
// 1. The tricycle (R = 0.3 m, l = 1 m) at beta0 = 0.35 rad driven at 0.5 m/s for one lap with
//    liftcheck's servo (rate = feed-forward + 40/s x angle error): the circle fitted to the
//    front-axle centre against the kinematic radius l / sin(beta0), and the engine's cost per step.
// 2. Two disks (radius 1 m) 3 m apart closing head-on at 1 m/s: the first step whose reported
//    contacts are not empty against the exact contact time 1 s.
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { dirname, resolve } from 'node:path';
import { createInterface } from 'node:readline';

const TIMEOUT_MS = 20000;

/// Leading --set KEY=VALUE options (the car's knobs), then the adapter.
function knobsOf(args) {
  const settings = {};
  while (args[0] === '--set' && /^[^=]+=.+$/.test(args[1] ?? '')) {
    const [key, value] = args[1].split('=');
    settings[key] = value;
    args = args.slice(2);
  }
  return { settings, rest: args };
}

function commandOf(args) {
  if (args.length === 1 && args[0].endsWith('.json')) {
    const reg = JSON.parse(readFileSync(args[0], 'utf8'));
    const dir = dirname(resolve(args[0]));
    return { argv: reg.command, cwd: dir, name: reg.name };
  }
  return { argv: args, cwd: process.cwd(), name: args.join(' ') };
}

/// The child and a request function: one line out, one line back (or an error after TIMEOUT_MS).
function connect({ argv, cwd }) {
  const child = spawn(argv[0], argv.slice(1), { cwd, stdio: ['pipe', 'pipe', 'inherit'] });
  const lines = createInterface({ input: child.stdout })[Symbol.asyncIterator]();
  const request = async (msg) => {
    child.stdin.write(JSON.stringify(msg) + '\n');
    let timer;
    const timeout = new Promise((_, fail) => { timer = setTimeout(() => fail(new Error(`no reply to ${msg.op} within ${TIMEOUT_MS} ms`)), TIMEOUT_MS); });
    const next = await Promise.race([lines.next(), timeout]).finally(() => clearTimeout(timer));
    if (next.done) throw new Error(`the adapter exited (after ${msg.op})`);
    const reply = JSON.parse(next.value);
    if (!reply.ok) throw new Error(`${msg.op}: ${reply.error}`);
    return reply;
  };
  return { child, request };
}

/// Least-squares circle through the points (x^2 + y^2 + D x + E y + F = 0, Kasa's fit).
function fitCircle(pts) {
  const n = pts.length, mx = pts.reduce((s, p) => s + p[0], 0) / n, my = pts.reduce((s, p) => s + p[1], 0) / n;
  let suu = 0, suv = 0, svv = 0, suuu = 0, svvv = 0, suvv = 0, svuu = 0;
  for (const [x, y] of pts) {
    const u = x - mx, v = y - my;
    suu += u * u; suv += u * v; svv += v * v;
    suuu += u * u * u; svvv += v * v * v; suvv += u * v * v; svuu += v * u * u;
  }
  const b1 = 0.5 * (suuu + suvv), b2 = 0.5 * (svvv + svuu), det = suu * svv - suv * suv;
  const uc = (b1 * svv - b2 * suv) / det, vc = (suu * b2 - suv * b1) / det;
  return Math.sqrt(uc * uc + vc * vc + (suu + svv) / n);
}

async function checkCar(request, settings) {
  const R = 0.3, l = 1.0, beta0 = 0.35, speed = 0.5, dt = 0.001, gain = 40;
  const car = { R_m: R, l_m: l, track_m: 0.8, wheels: 3, parallel_steering: false, wheel_width_m: 0.09, wheel_shape: 'sphere',
    chassis_height_m: 0.1, chassis_mass_kg: 40, wheel_mass_kg: 2, knuckle_mass_kg: 2 };
  let s = await request({ op: 'car', settings, dt_s: dt, mu: 1, gravity_W: [0, 0, -9.81], car,
    q0: { x_m: 0, y_m: 0, phi_rad: 0, beta_rad: beta0 }, servo: { spin_torque_max_Nm: 500, steer_torque_max_Nm: 500 } });
  const radius = l / Math.sin(beta0), lap_s = (2 * Math.PI * radius) / speed;
  let alpha = 0, engine_s = 0, steps = 0, path_m = 0, last = null;
  const across = [0, 0, 0], across_sq = [0, 0, 0];  // sideways slip of each wheel's contact point: largest, sum of squares
  const pts = [];
  const t0 = process.hrtime.bigint();
  const settle = Math.round(0.5 / dt), drive = Math.round(lap_s / dt);
  for (let k = -settle; k < drive; k++) {
    const t1 = (k + 1) * dt, driving = k >= 0;
    const rate = driving ? speed / R : 0, target = driving ? rate * t1 : 0;
    const prev = s.spin_joint_rad[0];
    s = await request({ op: 'step', spin_radps: [rate + gain * (target - alpha), 0], steer_radps: [gain * (beta0 - s.steer_rad[0]), 0], dt_s: dt });
    alpha = k === -1 ? 0 : alpha + wrap(s.spin_joint_rad[0] - prev);
    engine_s += s.engine_s;
    steps += 1;
    if (driving && last) path_m += Math.hypot(s.x_m - last[0], s.y_m - last[1]);
    if (driving) last = [s.x_m, s.y_m];
    if (driving && k % 10 === 0) pts.push([s.x_m, s.y_m]);
    if (driving) s.wheels.forEach((w, i) => { const u = sideSlip(w); across[i] = Math.max(across[i], Math.abs(u)); across_sq[i] += u * u; });
  }
  const wall_s = Number(process.hrtime.bigint() - t0) * 1e-9;
  const fitted = fitCircle(pts);
  console.log(`car:   fitted radius ${fitted.toFixed(5)} m, l/sin(beta0) ${radius.toFixed(5)} m, ` +
    `error ${((fitted / radius - 1) * 100).toFixed(3)} %; path ${((path_m / (speed * (drive - 1) * dt) - 1) * 100).toFixed(3)} % against v t; final beta ${s.steer_rad[0].toFixed(4)} rad, wheel z ${s.z_m.toFixed(5)} m`);
  const mm = (v) => (v * 1e3).toFixed(2);
  console.log(`       sideways slip of the contact points (front, rear left, rear right): largest ${across.map(mm).join(', ')} mm/s, ` +
    `rms ${across_sq.map((q) => mm(Math.sqrt(q / drive))).join(', ')} mm/s`);
  console.log(`       engine ${(engine_s / steps * 1e6).toFixed(1)} us/step, round trip ${(wall_s / steps * 1e6).toFixed(1)} us/step (${steps} steps)`);
}

/// The sideways speed of a wheel's contact point straight below its hub (v + w x (0, 0, -z)) along
/// its horizontal axle.
function sideSlip({ v_hub_W: v, omega_W: w, axle_W: a, hub_z_m: z }) {
  const vc = [v[0] - w[1] * z, v[1] + w[0] * z], n = Math.hypot(a[0], a[1]);
  return (vc[0] * a[0] + vc[1] * a[1]) / n;
}

function wrap(a) {
  return a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));
}

async function checkDisks(request) {
  const dt = 0.001, v = 0.5;  // each disk at 0.5 m/s: closing at 1 m/s, surfaces 1 m apart
  let s = await request({ op: 'disks', settings: {}, radius_m: 1, dt_s: dt, cM0: [0, 0], cN0: [3, 0] });
  let engine_s = 0;
  for (let k = 1; k <= 2000; k++) {
    const cN_next = [3 - v * k * dt, 0];
    s = await request({ op: 'step', vM_cmd: [v, 0], cN_next, vN: [-v, 0], dt_s: dt });
    engine_s += s.engine_s;
    if (s.contacts.count > 0) {
      console.log(`disks: first contact in step ${k} (starts at t = ${((k - 1) * dt).toFixed(3)} s; exact contact 1.000 s), ` +
        `${s.contacts.count} point(s), signed distance ${s.contacts.distance_min_m.toExponential(2)} m; ` +
        `engine ${(engine_s / k * 1e6).toFixed(1)} us/step`);
      return;
    }
  }
  console.log('disks: no contact reported within 2 s');
}

const { settings, rest } = knobsOf(process.argv.slice(2));
const target = commandOf(rest);
if (!target.argv?.length) {
  console.error('usage: node check.mjs NAME.json | COMMAND ARG...');
  process.exit(2);
}
const { child, request } = connect(target);
try {
  const hello = await request({ op: 'hello', protocol: 1 });
  console.log(`${target.name}: ${hello.engine} ${hello.version} (${hello.precision}); knobs: ${hello.settings.map((k) => `${k.key}=${k.default}`).join(', ') || 'none'}`);
  await checkCar(request, settings);
  await checkDisks(request);
  await request({ op: 'bye' });
} catch (e) {
  console.error(`check: ${e.message}`);
  child.kill();
  process.exit(1);
}
