// A quick check of an engine adapter (docs/protocol.md), for adapter authors:
//   node check.mjs NAME.json            (a registration file: its command is run)
//   node check.mjs node rapier.mjs --config default
//   node check.mjs --set iterations=50 cannon.json      (knob values for the car)
//   node check.mjs --wheels 4 cannon.json               (the four-wheel Ackermann car)
// 1. The tricycle (R = 0.3 m, l = 1 m; or the four-wheel car) at beta0 = 0.35 rad driven at 0.5 m/s for one lap with
//    liftcheck's servo (rate = feed-forward + 40/s x angle error): the circle fitted to the
//    front-axle centre against the kinematic radius l / sin(beta0), and the engine's cost per step.
// 2. Two disks (radius 1 m) 3 m apart closing head-on at 1 m/s: the first step whose reported
//    contacts are not empty against the exact contact time 1 s, and M's spin held (wM).
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { dirname, resolve } from 'node:path';
import { createInterface } from 'node:readline';

const TIMEOUT_MS = 20000;

/// Leading options: --set KEY=VALUE (the car's knobs), --wheels 3|4; then the adapter.
function optionsOf(args) {
  const settings = {};
  let wheels = 3;
  for (;;) {
    if (args[0] === '--set' && /^[^=]+=.+$/.test(args[1] ?? '')) {
      const [key, value] = args[1].split('=');
      settings[key] = value;
    } else if (args[0] === '--wheels' && ['3', '4'].includes(args[1])) wheels = Number(args[1]);
    else return { settings, wheels, rest: args };
    args = args.slice(2);
  }
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
  let numbered = 0;
  const request = async (msg) => {
    const id = ++numbered;  // every request numbered; its reply must carry the number (docs/protocol.md)
    child.stdin.write(JSON.stringify({ id, ...msg }) + '\n');
    let timer;
    const timeout = new Promise((_, fail) => { timer = setTimeout(() => fail(new Error(`no reply to ${msg.op} within ${TIMEOUT_MS} ms`)), TIMEOUT_MS); });
    const next = await Promise.race([lines.next(), timeout]).finally(() => clearTimeout(timer));
    if (next.done) throw new Error(`the adapter exited (after ${msg.op})`);
    const reply = JSON.parse(next.value);
    if (reply.id !== id) throw new Error(`${msg.op}: the reply is numbered ${JSON.stringify(reply.id)}, the request ${id}`);
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

/// Front wheel k's steering angle and drive ratio at the car's steering beta: the tricycle's one
/// wheel (beta, 1), or the four-wheel car's left and right at their Ackermann angles, driven at
/// their turning radius over the front-axle centre's (models/ackermann.hpp).
function frontGeometry(wheels, beta, l, track) {
  if (wheels === 3) return [{ beta_rad: beta, rho: 1 }];
  const k = track / (2 * l);
  return [1, -1].map((s) => ({ beta_rad: Math.atan2(Math.sin(beta), Math.cos(beta) - s * k * Math.sin(beta)),
    rho: Math.hypot(Math.sin(beta), Math.cos(beta) - s * k * Math.sin(beta)) }));
}

async function checkCar(request, settings, wheels) {
  const R = 0.3, l = 1.0, track = 0.8, beta0 = 0.35, speed = 0.5, dt = 0.001, gain = 40;
  const car = { R_m: R, l_m: l, track_m: track, wheels, parallel_steering: false, wheel_width_m: 0.09, wheel_shape: 'sphere',
    chassis_height_m: 0.1, chassis_mass_kg: 40, wheel_mass_kg: 2, knuckle_mass_kg: 2 };
  let s = await request({ op: 'car', settings, dt_s: dt, mu: 1, gravity_W: [0, 0, -9.81], car,
    q0: { x_m: 0, y_m: 0, phi_rad: 0, beta_rad: beta0 }, servo: { spin_torque_max_Nm: 500, steer_torque_max_Nm: 500 } });
  const fronts = frontGeometry(wheels, beta0, l, track);
  const radius = l / Math.sin(beta0), lap_s = (2 * Math.PI * radius) / speed;
  let alpha = 0, engine_s = 0, steps = 0, path_m = 0, last = null;
  const across = Array(wheels).fill(0), across_sq = Array(wheels).fill(0);  // sideways slip of each wheel's contact point: largest, sum of squares
  const pts = [];
  const t0 = process.hrtime.bigint();
  const settle = Math.round(0.5 / dt), drive = Math.round(lap_s / dt);
  for (let k = -settle; k < drive; k++) {
    const t1 = (k + 1) * dt, driving = k >= 0;
    const rate = driving ? speed / R : 0, target = driving ? rate * t1 : 0;
    const prev = s.spin_joint_rad.slice(), roll = rate + gain * (target - alpha);
    const spin = fronts.map((f) => f.rho * roll), steer = fronts.map((f, i) => gain * (f.beta_rad - s.steer_rad[i]));
    s = await request({ op: 'step', spin_radps: [spin[0], spin[1] ?? 0], steer_radps: [steer[0], steer[1] ?? 0], dt_s: dt });
    const d_alpha = fronts.reduce((a, f, i) => a + wrap(s.spin_joint_rad[i] - prev[i]) / f.rho, 0) / fronts.length;
    alpha = k === -1 ? 0 : alpha + d_alpha;
    engine_s += s.engine_s;
    steps += 1;
    if (driving && last) path_m += Math.hypot(s.x_m - last[0], s.y_m - last[1]);
    if (driving) last = [s.x_m, s.y_m];
    if (driving && k % 10 === 0) pts.push([s.x_m, s.y_m]);
    if (driving) s.wheels.forEach((w, i) => { const u = sideSlip(w); across[i] = Math.max(across[i], Math.abs(u)); across_sq[i] += u * u; });
  }
  const wall_s = Number(process.hrtime.bigint() - t0) * 1e-9;
  const fitted = fitCircle(pts);
  console.log(`car:   ${wheels} wheels: fitted radius ${fitted.toFixed(5)} m, l/sin(beta0) ${radius.toFixed(5)} m, ` +
    `error ${((fitted / radius - 1) * 100).toFixed(3)} %; path ${((path_m / (speed * (drive - 1) * dt) - 1) * 100).toFixed(3)} % against v t; ` +
    `final steering ${s.steer_rad.slice(0, fronts.length).map((b) => b.toFixed(4)).join(', ')} rad, front wheel z ${s.z_m.toFixed(5)} m`);
  const mm = (v) => (v * 1e3).toFixed(2);
  console.log(`       sideways slip of the contact points (${wheels === 3 ? 'front' : 'front left, front right'}, rear left, rear right): ` +
    `largest ${across.map(mm).join(', ')} mm/s, rms ${across_sq.map((q) => mm(Math.sqrt(q / drive))).join(', ')} mm/s`);
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
  let s = await request({ op: 'disks', settings: {}, radius_m: 1, mu_MN: 0, dt_s: dt, cM0: [0, 0], cN0: [3, 0] });
  let engine_s = 0;
  for (let k = 1; k <= 2000; k++) {
    const cN_next = [3 - v * k * dt, 0];
    s = await request({ op: 'step', vM_cmd: [v, 0], cN_next, vN: [-v, 0], dt_s: dt });
    engine_s += s.engine_s;
    if (!Array.isArray(s.wM) || s.wM.length !== 3) throw new Error(`step ${k}: the reply has no wM [wx, wy, wz] (M's angular velocity, protocol 3)`);
    if (!(Math.hypot(...s.wM) <= 1e-6)) throw new Error(`disks: M turns at ${Math.hypot(...s.wM).toExponential(2)} rad/s after step ${k}: its spin must be held (spin_M_max, 1e-6 rad/s)`);
    if (s.contacts.count > 0) {
      console.log(`disks: first contact in step ${k} (starts at t = ${((k - 1) * dt).toFixed(3)} s; exact contact 1.000 s), ` +
        `${s.contacts.count} point(s), signed distance ${s.contacts.distance_min_m.toExponential(2)} m; ` +
        `engine ${(engine_s / k * 1e6).toFixed(1)} us/step`);
      return;
    }
  }
  console.log('disks: no contact reported within 2 s');
}

const { settings, wheels, rest } = optionsOf(process.argv.slice(2));
const target = commandOf(rest);
if (!target.argv?.length) {
  console.error('usage: node check.mjs NAME.json | COMMAND ARG...');
  process.exit(2);
}
const { child, request } = connect(target);
try {
  const hello = await request({ op: 'hello', protocol: 3 });
  console.log(`${target.name}: ${hello.engine} ${hello.version} (${hello.precision}); knobs: ${hello.settings.map((k) => `${k.key}=${k.default}`).join(', ') || 'none'}`);
  await checkCar(request, settings, wheels);
  await checkDisks(request);
  await request({ op: 'bye' });
} catch (e) {
  console.error(`check: ${e.message}`);
  child.kill();
  process.exit(1);
}
