// Tests of the adapters' side of the protocol (node --test test.mjs, or npm test): every
// registered configuration's hello, the refusal of bad knobs and of a step without a world, and
// the two faults of cannon.mjs, each against the clean adapter stepped the same way.
import { after, test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { readFileSync, readdirSync } from 'node:fs';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { dirname } from 'node:path';
import { PROTOCOL } from './protocol.mjs';

const DIR = dirname(fileURLToPath(import.meta.url));
const SUITE = `${DIR}/suite`;
const REGISTERED = readdirSync(SUITE).filter((f) => f.endsWith('.json') && !f.startsWith('package'))
  .map((f) => JSON.parse(readFileSync(`${SUITE}/${f}`, 'utf8')));

/// An adapter child and a function sending one request, numbered, and returning its reply (10 s
/// at most), which must carry the request's number.
/// Every child started, ended after the last test (a failed assertion leaves its child running).
const CHILDREN = [];
after(() => { for (const c of CHILDREN) c.kill('SIGKILL'); });

function start(argv) {
  const child = spawn(argv[0], argv.slice(1), { cwd: SUITE, stdio: ['pipe', 'pipe', 'ignore'] });
  CHILDREN.push(child);
  const lines = createInterface({ input: child.stdout })[Symbol.asyncIterator]();
  let numbered = 0;
  const request = async (msg) => {
    const id = ++numbered;
    child.stdin.write(JSON.stringify({ id, ...msg }) + '\n');
    let timer;
    const timeout = new Promise((_, fail) => { timer = setTimeout(() => fail(new Error(`no reply to ${msg.op}`)), 10000); });
    const next = await Promise.race([lines.next(), timeout]).finally(() => clearTimeout(timer));
    assert.ok(!next.done, `the adapter exited after ${msg.op}`);
    const reply = JSON.parse(next.value);
    assert.equal(reply.id, id, `the reply to ${msg.op} carries its request's number`);
    return reply;
  };
  const stop = async () => { await request({ op: 'bye' }); };
  /// A request answered by `n` lines ("steps"), each carrying its number.
  const requestLines = async (msg, n) => {
    const id = ++numbered;
    child.stdin.write(JSON.stringify({ id, ...msg }) + '\n');
    const replies = [];
    for (let k = 0; k < n; k++) {
      let timer;
      const timeout = new Promise((_, fail) => { timer = setTimeout(() => fail(new Error(`${k} of ${n} lines to ${msg.op}`)), 10000); });
      const next = await Promise.race([lines.next(), timeout]).finally(() => clearTimeout(timer));
      assert.ok(!next.done, `the adapter exited after ${msg.op}`);
      replies.push(JSON.parse(next.value));
      assert.equal(replies[k].id, id);
    }
    return replies;
  };
  return { request, requestLines, stop };
}

const CAR = { R_m: 0.3, l_m: 1, track_m: 0.8, wheels: 3, parallel_steering: false, wheel_width_m: 0.09, wheel_shape: 'sphere',
  chassis_height_m: 0.1, chassis_mass_kg: 40, wheel_mass_kg: 2, knuckle_mass_kg: 2 };
const carRequest = (settings) => ({ op: 'car', settings, dt_s: 0.001, mu: 1, gravity_W: [0, 0, -9.81], car: CAR,
  q0: { x_m: 0, y_m: 0, phi_rad: 0, beta_rad: 0.35 }, servo: { spin_torque_max_Nm: 500, steer_torque_max_Nm: 500 } });

for (const reg of REGISTERED) {
  test(`${reg.name}: hello declares the protocol's version, a precision and knobs with their defaults in range`, async () => {
    const a = start(reg.command);
    const h = await a.request({ op: 'hello', protocol: PROTOCOL });
    assert.equal(h.ok, true);
    assert.equal(h.protocol, PROTOCOL);
    assert.ok(['float32', 'float64'].includes(h.precision));
    assert.deepEqual(h.vehicles, ['car', 'disks']);
    for (const k of h.settings) {
      if (k.kind === 'choice') assert.ok(k.choices.includes(k.default), k.key);
      else assert.ok(Number(k.default) >= k.min && Number(k.default) <= k.max, k.key);
    }
    assert.equal((await a.request({ op: 'hello', protocol: 1 })).ok, false);
    await a.stop();
  });

  test(`${reg.name}: bad knobs and a step without a world are refused`, async () => {
    const a = start(reg.command);
    const h = await a.request({ op: 'hello', protocol: PROTOCOL });
    const refused = async (msg, why) => {
      const r = await a.request(msg);
      assert.equal(r.ok, false, why);
      assert.equal(typeof r.error, 'string');
    };
    await refused({ op: 'step', spin_radps: [0, 0], steer_radps: [0, 0], dt_s: 0.001 }, 'a step before any build');
    await refused(carRequest({ no_such_knob: '1' }), 'an unknown knob');
    for (const k of h.settings.filter((s) => s.vehicle === 'car')) {
      if (k.kind === 'choice') await refused(carRequest({ [k.key]: 'no-such-choice' }), `${k.key} not one of its choices`);
      else await refused(carRequest({ [k.key]: String(k.max + 1) }), `${k.key} above its range`);
    }
    assert.equal((await a.request(carRequest({}))).ok, true);
    await refused({ ...carRequest({}), car: { ...CAR, wheels: 5 } }, 'a car with five wheels');
    await refused({ op: 'step', spin_radps: [0, 0], steer_radps: [0, 0], dt_s: 0.001 }, 'a step after a failed build (it drops the car before it)');
    await a.stop();
  });
}

/// x of the front-axle centre after each of n steps of a car driven at 1 rad/s.
async function drive(argv, n) {
  const a = start(argv);
  await a.request({ op: 'hello', protocol: PROTOCOL });
  await a.request(carRequest({}));
  const xs = [];
  for (let k = 0; k < n; k++) xs.push((await a.request({ op: 'step', spin_radps: [1, 0], steer_radps: [0, 0], dt_s: 0.001 })).x_m);
  await a.stop();
  return xs;
}

/// The first step with a reported contact, disks closing at 1 m/s from 1 m apart.
async function firstContact(argv) {
  const a = start(argv);
  await a.request({ op: 'hello', protocol: PROTOCOL });
  await a.request({ op: 'disks', settings: {}, radius_m: 1, mu_MN: 0, dt_s: 0.001, cM0: [0, 0], cN0: [2.0105, 0] });
  for (let k = 1; k <= 100; k++) {
    const r = await a.request({ op: 'step', vM_cmd: [1, 0], cN_next: [2.0105, 0], vN: [0, 0], dt_s: 0.001 });
    if (r.contacts.count > 0) {
      await a.stop();
      return k;
    }
  }
  await a.stop();
  return null;
}

test('cannon --fault stale-pose reports the previous step\'s front-axle position', async () => {
  const clean = await drive(['node', '../cannon.mjs', '--config', 'default'], 50);
  const stale = await drive(['node', '../cannon.mjs', '--config', 'default', '--fault', 'stale-pose'], 50);
  assert.ok(clean[49] - clean[0] > 1e-3, 'the car moves');
  for (let k = 1; k < 50; k++) assert.equal(stale[k], clean[k - 1]);
});

// "steps" (docs/protocol.md): the protocol loop applies liftcheck's servo law for the tricycle and
// books the wheel angle as liftcheck does; the replies are those of the same rates sent one step at
// a time, each with the rates applied.
test('cannon: "steps" replies as the same steps one at a time, with the servo law\'s rates', async () => {
  const [ka, kb] = [40, 40];
  const targets = [[0.01, 0.36, 2.0, 0.5], [0.02, 0.365, 2.5, 0.5], [0.05, 0.37, 3.0, -0.5]];
  const planned = start(['node', '../cannon.mjs', '--config', 'default']);
  const hello = await planned.request({ op: 'hello', protocol: PROTOCOL });
  assert.equal(hello.servo_steps, true);
  const built = await planned.request(carRequest({}));
  const lines = await planned.requestLines({ op: 'steps', dt_s: 0.001, spin_gain_per_s: ka, steer_gain_per_s: kb, alpha_rad: 0,
    spin_rad: built.spin_joint_rad[0], steer_rad: built.steer_rad[0], targets }, targets.length);
  await planned.stop();
  const single = start(['node', '../cannon.mjs', '--config', 'default']);
  await single.request({ op: 'hello', protocol: PROTOCOL });
  let s = await single.request(carRequest({}));
  let alpha = 0;
  for (const [k, [ta, tb, ra, rb]] of targets.entries()) {
    const spin = ra + ka * (ta - alpha), steer = rb + kb * (tb - s.steer_rad[0]);
    const next = await single.request({ op: 'step', spin_radps: [spin, 0], steer_radps: [steer, 0], dt_s: 0.001 });
    assert.deepEqual(lines[k].applied, [spin, steer]);
    assert.deepEqual({ ...lines[k], applied: undefined, id: 0, engine_s: 0 }, { ...next, applied: undefined, id: 0, engine_s: 0 });
    let d = (next.spin_joint_rad[0] - s.spin_joint_rad[0] + Math.PI) % (2 * Math.PI);  // liftcheck's wrap_angle
    if (d <= 0) d += 2 * Math.PI;
    alpha += d - Math.PI;
    s = next;
  }
  assert.ok(lines[2].x_m !== lines[0].x_m, 'the car moves');
  await single.stop();
});

test('cannon --fault late-contact reports the disks\' first contact one step late', async () => {
  const clean = await firstContact(['node', '../cannon.mjs', '--config', 'default']);
  assert.equal(clean, 12);  // the gap of 10.5 mm is closed during step 11: the state step 12 starts from overlaps
  assert.equal(await firstContact(['node', '../cannon.mjs', '--config', 'default', '--fault', 'late-contact']), clean + 1);
});

// Havok runs as its users run it: the ideal step time is the step it is called with. Havok has no
// getter for it (HavokPhysics.d.ts 1.3.14 has HP_World_SetIdealStepTime only): the adapter sends
// back the value it set, for the car and the disks, at two steps.
test('havok: the ideal step time set is the request\'s dt, for two dt', async () => {
  const reg = REGISTERED.find((r) => r.name === 'havok');
  const a = start(reg.command);
  assert.equal((await a.request({ op: 'hello', protocol: PROTOCOL })).ok, true);
  for (const dt_s of [0.001, 0.002]) {
    const car = await a.request({ ...carRequest({}), dt_s });
    assert.equal(car.ok, true);
    assert.equal(car.ideal_step_time_s, dt_s);
    const disks = await a.request({ op: 'disks', settings: {}, radius_m: 1, mu_MN: 0, dt_s, cM0: [0, 0], cN0: [3, 0] });
    assert.equal(disks.ideal_step_time_s, dt_s);
  }
  await a.stop();
});

// What Havok was given, seen in what it does: a car driven 300 steps of 1 ms at its default ends
// exactly where it does with the ideal step time set to dt, and elsewhere with Havok's 1/60 s (the
// solver's stiffness adapted to a 60 Hz step). A hard-coded ideal step time fails one of the two.
async function havokEnd(settings) {
  const a = start(REGISTERED.find((r) => r.name === 'havok').command);
  assert.equal((await a.request({ op: 'hello', protocol: PROTOCOL })).ok, true);
  assert.equal((await a.request(carRequest(settings))).ok, true);
  let s = null;
  for (let k = 0; k < 300; k++) s = await a.request({ op: 'step', spin_radps: [3, 0], steer_radps: [0.2, 0], dt_s: 0.001 });
  await a.stop();
  return [s.x_m, s.y_m, s.phi_rad];
}
test('havok: the ideal step time Havok steps with is dt (its motion as with ideal_step_time=dt, not 1/60)', async () => {
  const standard = await havokEnd({}), at_dt = await havokEnd({ ideal_step_time: 'dt' }), at_60 = await havokEnd({ ideal_step_time: '1/60' });
  assert.deepEqual(standard, at_dt);
  assert.ok(Math.hypot(standard[0] - at_60[0], standard[1] - at_60[1]) > 1e-6, `1/60 s moves the car as dt does: ${standard} against ${at_60}`);
});

// cannon-es's Equation constructor gives every equation setSpookParams(1e7, 4, 1/60) (Equation.js,
// 0.20.0); the adapter re-sets the constraints' equations for the run's dt. Its build reply lists
// [a, b, eps] of each, read back from the equations.
function spook(k, d, h) {  // Equation.setSpookParams
  return [4 / (h * (1 + 4 * d)), (4 * d) / (1 + 4 * d), 4 / (h * h * k * (1 + 4 * d))];
}
for (const name of ['cannon', 'cannon-accurate']) {
  test(`${name}: every constraint equation's SPOOK parameters are those of the run's dt`, async () => {
    const reg = REGISTERED.find((r) => r.name === name);
    const a = start(reg.command);
    assert.equal((await a.request({ op: 'hello', protocol: PROTOCOL })).ok, true);
    for (const [wheels, count] of [[3, 4 * 6], [4, 6 * 6]]) {  // hinges x (3 point, 2 rotational, 1 motor)
      for (const dt_s of [0.001, 0.002]) {
        const r = await a.request({ ...carRequest({}), dt_s, car: { ...CAR, wheels } });
        assert.equal(r.ok, true);
        assert.equal(r.constraint_spook.length, count);
        const want = spook(1e7, 4, dt_s);
        for (const got of r.constraint_spook)
          got.forEach((v, i) => assert.ok(Math.abs(v - want[i]) <= 1e-12 * Math.abs(want[i]), `${['a', 'b', 'eps'][i]} = ${v}, want ${want[i]} at dt ${dt_s}`));
      }
    }
    await a.stop();
  });
}

// PhysX (physx.mjs): the car drives the way it is told on every configuration (the sign of each
// drive: PxRevoluteJoint's drive velocity is the child's relative to the parent, an articulation
// joint's likewise), M's spin is held on the disks, and the contacts PhysX reports for the pair
// come with their signed distances: none while the disks are further apart than the two contact
// offsets (0.04 m), a speculative one from there on.
for (const name of ['physx', 'physx-tgs', 'physx-articulation']) {
  test(`${name}: the front wheel rolls forward and steers left when told to`, async () => {
    const a = start(REGISTERED.find((r) => r.name === name).command);
    assert.equal((await a.request({ op: 'hello', protocol: PROTOCOL })).ok, true);
    const first = await a.request({ ...carRequest({}), servo: { spin_torque_max_Nm: 105.9, steer_torque_max_Nm: 105.9 } });
    assert.equal(first.ok, true);
    let s = first;
    for (let k = 0; k < 300; k++) s = await a.request({ op: 'step', spin_radps: [2, 0], steer_radps: [0.1, 0], dt_s: 0.001 });
    assert.ok(s.spin_joint_rad[0] > 0.1, `spin angle ${s.spin_joint_rad[0]} after 0.3 s at 2 rad/s (the sign; PGS at 4 iterations lags: 0.27 rad)`);
    assert.ok(s.steer_rad[0] > 0.36 && s.steer_rad[0] < 0.39, `steering ${s.steer_rad[0]}, want about 0.38`);
    assert.ok(s.x_m > 0.02, `the front axle moved ${s.x_m} m forward`);
    assert.ok(Math.abs(s.z_m - 0.3) < 1e-3, `the front wheel rests on the ground: hub at ${s.z_m} m`);
    await a.stop();
  });

  test(`${name}: disk contacts are PhysX's reports, M's spin held`, async () => {
    const a = start(REGISTERED.find((r) => r.name === name).command);
    assert.equal((await a.request({ op: 'hello', protocol: PROTOCOL })).ok, true);
    assert.equal((await a.request({ op: 'disks', settings: {}, radius_m: 1, mu_MN: 0.5, dt_s: 0.001, cM0: [0, 0], cN0: [2.1, 0.5] })).ok, true);
    let first = null, r = null;
    for (let k = 1; k <= 200; k++) {
      r = await a.request({ op: 'step', vM_cmd: [1, 0], cN_next: [2.1, 0.5], vN: [0, 0], dt_s: 0.001 });
      assert.deepEqual(r.wM.map(Math.abs), [0, 0, 0], `M turned at step ${k}`);
      if (r.contacts.count > 0 && first === null) first = { k, r };
    }
    const gap0 = Math.hypot(2.1, 0.5) - 2;  // 0.1602 m, closed at 1 m/s along x
    assert.ok(first !== null, 'a contact is reported');
    assert.ok(first.r.contacts.distance_min_m > 0 && first.r.contacts.distance_min_m <= 0.04 + 1e-6, `first reported at distance ${first.r.contacts.distance_min_m}`);
    assert.ok(first.k > 100, `first contact at step ${first.k}, the disks ${gap0} m apart at the start`);
    assert.ok(r.contacts.count > 0, 'still in contact');
    await a.stop();
  });
}
