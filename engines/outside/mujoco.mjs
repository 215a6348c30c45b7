// MuJoCo 3 (mujoco-js, the official WASM build, float64) served over liftcheck's engine protocol
// (docs/protocol.md), with the MJCF of liftcheck's compiled-in MuJoCo adapter
// (engines/mujoco/mujoco_engine.cpp). Two configurations, chosen with --config:
//   default   MuJoCo's defaults as shipped (the compiled-in `mujoco`).
//   stiff     the compiled-in `mujoco-stiff`'s changes: every geom's solref (2 dt, 1), the
//             stiffest time constant MuJoCo's refsafe allows (2 x timestep), the elliptic friction
//             cone and impratio 10 (knob `impratio`, the car's only, as there).
//
// The model is MJCF text written into the module's in-memory file system and compiled by
// MjModel.loadFromXML. Stepping is mj_step split in its halves, as in the compiled-in adapter:
// mj_step2 integrates the state whose kinematics, velocities and contacts the previous mj_step1
// computed (with the controls set in between), then mj_step1 computes those of the new state;
// with the Euler integrator this is mj_step. So the state read between steps is the current one,
// and the contacts a step uses are those of the state it starts from.
//
// Car: a free-joint chassis whose origin is the front-axle centre, a box l/2 behind it (no
// collision); a knuckle hinged about the chassis z, the front wheel hinged about the knuckle's y,
// the rear wheels about the chassis y; sphere wheels (condim 3) on a ground plane; <velocity>
// actuators (kv = the joint's own inertia / dt, force-limited to the request's torque; in a
// braked run one more on each rear wheel's hinge, ctrl 0, limited to the brake's torque). The
// four-wheel car has two knuckles at (0, +-track/2), named with _left and _right.
// Disks: M a sphere on slide joints x and y with velocity actuators kv = 1 kg / dt, N a mocap
// sphere placed on its path after each step; frictionless (condim 1), no gravity.
//
//   node mujoco.mjs --config default|stiff
import loadMujoco from 'mujoco-js';

import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';

console.log = console.error;  // MuJoCo's warnings must not reach standard output
const mj = await loadMujoco();
const CONFIGS = { default: { stiff: false }, stiff: { stiff: true, impratio: 10 } };
const CONFIG = CONFIGS[C.parseArgs(process.argv.slice(2), CONFIGS).config];
// The compiled-in configurations' knobs (engines/mujoco/mujoco_engine.cpp): mujoco-stiff's impratio,
// the car's (the disks are frictionless); mujoco's solref time constant (cars and disks) and
// friction cone (the car's).
const TIMECONST_DEFAULT_S = 0.02;  // MuJoCo's default solref[0]
const timeconstKnob = (vehicle) => ({ key: 'solref_timeconst_s', vehicle, kind: 'real', min: 0, min_exclusive: true, max: 1, default: '0.02',
  help: 'time constant of the contacts\' soft constraint: solref[0] of the geom defaults (MuJoCo\'s default 0.02 s), damping ratio 1; '
    + 'at least 2 dt, refsafe\'s floor, to which MuJoCo would raise a smaller one without a word' });
const KNOBS = CONFIG.stiff
  ? [{ key: 'impratio', vehicle: 'car', kind: 'real', min: 0, min_exclusive: true, max: 1000, default: String(CONFIG.impratio),
      help: 'ratio of frictional to normal constraint impedance (option impratio)' }]
  : [timeconstKnob('car'), timeconstKnob('disks'),
     { key: 'cone', vehicle: 'car', kind: 'choice', choices: ['pyramidal', 'elliptic'], default: 'pyramidal',
       help: 'friction cone (option cone): pyramidal, MuJoCo\'s default, or elliptic' }];
const DIR = '/liftcheck';
mj.FS.mkdir(DIR);
const num = (x) => x.toPrecision(17);
const OBJ = { geom: mj.mjtObj.mjOBJ_GEOM.value, body: mj.mjtObj.mjOBJ_BODY.value, joint: mj.mjtObj.mjOBJ_JOINT.value, actuator: mj.mjtObj.mjOBJ_ACTUATOR.value };
const BAD = [['qpos', mj.mjtWarning.mjWARN_BADQPOS], ['qvel', mj.mjtWarning.mjWARN_BADQVEL], ['qacc', mj.mjtWarning.mjWARN_BADQACC]];
let sim = null, car = null, disks = null;

/// A compiled model and its data; the previous ones are freed.
function compile(xml) {
  if (sim) {
    sim.d.delete();
    sim.m.delete();
    sim = null;
  }
  const path = `${DIR}/model.xml`;
  mj.FS.writeFile(path, xml);
  let m;
  try {
    m = mj.MjModel.loadFromXML(path);
  } catch (e) {
    throw new Error(`MuJoCo could not compile the model: ${e?.message ?? e}`);
  }
  if (!m) throw new Error('MuJoCo could not compile the model');
  sim = { m, d: new mj.MjData(m) };
  const id = (type, name) => {
    const i = mj.mj_name2id(m, OBJ[type], name);
    if (i < 0) throw new Error(`MuJoCo model has no ${type} named ${name}`);
    return i;
  };
  mj.mj_step1(m, sim.d);
  check();
  return id;
}

/// MuJoCo resets a state with NaN or huge values and warns; that is an engine error here.
/// d.warning is a copy of MuJoCo's warning array made at each reading: read once.
function check() {
  const warnings = sim.d.warning;
  try {
    for (const [what, w] of BAD) {
      const stat = warnings.get(w.value);
      const n = stat.number;
      stat.delete?.();
      if (n > 0) throw new Error(`MuJoCo reported a bad state (${what}) at t = ${sim.d.time.toFixed(4)} s`);
    }
  } finally {
    warnings.delete?.();
  }
}

/// The step's dt (a run's last step may be shorter, or differ from the build's by rounding): the
/// model's option timestep; the actuator gains stay those of the build's dt.
function timestep(dt_s) {
  if (sim.m.opt.timestep !== dt_s) sim.m.opt.timestep = dt_s;
}

/// The <option> element and the geom defaults at time step dt: mujoco_engine.cpp's option_xml. A
/// time constant under refsafe's floor of 2 dt is refused: MuJoCo would raise it without a word.
function option(dt_s, g, { impratio, solref_timeconst_s: tc = TIMECONST_DEFAULT_S, cone = 'pyramidal' }) {
  const base = `timestep="${num(dt_s)}" gravity="${g.map(num).join(' ')}"`;
  if (!CONFIG.stiff) {
    if (!(tc >= 2 * dt_s)) throw new Error(`setting solref_timeconst_s = ${tc} s is below 2 dt = ${2 * dt_s} s, the floor MuJoCo's refsafe raises it to without a word`);
    return `<option ${base}${cone === 'elliptic' ? ' cone="elliptic"' : ''}/>
<default><geom solref="${num(tc)} 1"/></default>`;
  }
  return `<option ${base} cone="elliptic" impratio="${num(impratio)}"/>
<default><geom solref="${num(2 * dt_s)} 1"/></default>`;
}

/// The brake of a braked run (servo.rear_brake_Nm > 0, docs/protocol.md; '' otherwise, the model
/// as before): a <velocity> actuator on each rear wheel's hinge, as the front spin's (kv = the
/// wheel's own inertia about its axle / dt, force-limited to the brake's torque), its ctrl held at
/// 0 (stepCar). MuJoCo's documented velocity servo, force = kv (ctrl - qvel), with forcelimited
/// clamping it to forcerange: https://mujoco.readthedocs.io/en/stable/XMLreference.html#actuator-velocity
/// (and #actuator-general for forcelimited / forcerange); as engines/mujoco/mujoco_engine.cpp's brakes_xml.
function brakesXml(brake_Nm, wheelI, dt_s) {
  if (!(brake_Nm > 0)) return '';
  return ['rear_left', 'rear_right'].map((j) => `
<velocity name="brake_${j}" joint="${j}" kv="${num(wheelI / dt_s)}" forcelimited="true" forcerange="${num(-brake_Nm)} ${num(brake_Nm)}"/>`).join('');
}

function carXml({ car: d, q0, servo, mu, dt_s, gravity_W }, knob) {
  const R = d.R_m, l = d.l_m, w = d.track_m;
  const ik = d.knuckle_mass_kg * C.KNUCKLE_GYRATION_SQ_M2;
  const spinI = 0.4 * d.wheel_mass_kg * R * R, steerI = spinI + ik;  // kv = I / dt: deadbeat when unloaded
  const wheel = `<geom type="sphere" size="${num(R)}" mass="${num(d.wheel_mass_kg)}" condim="3" friction="${num(mu)} 0.005 0.0001" contype="1" conaffinity="2"/>`;
  const [, , qz, qw] = C.yawQuat(q0.phi_rad);
  // The tricycle's one knuckle (named as in the compiled-in model) or the four-wheel car's two.
  const fronts = C.frontWheels(d, q0.beta_rad).map((f, k, all) => ({ ...f, sfx: all.length === 1 ? '' : ['_left', '_right'][k] }));
  const knuckles = fronts.map(({ y_m, beta0_rad, sfx }) => {
    const [, , bz, bw] = C.yawQuat(beta0_rad);
    return `  <body name="knuckle${sfx}" pos="0 ${num(y_m)} 0" quat="${num(bw)} 0 0 ${num(bz)}">
    <joint name="steer${sfx}" type="hinge" axis="0 0 1"/>
    <inertial pos="0 0 0" mass="${num(d.knuckle_mass_kg)}" diaginertia="${num(ik)} ${num(ik)} ${num(ik)}"/>
    <body name="front${sfx}"><joint name="spin${sfx}" type="hinge" axis="0 1 0"/>${wheel}</body>
  </body>`;
  }).join('\n');
  const actuators = fronts.map(({ sfx }) =>
    `<velocity name="spin${sfx}" joint="spin${sfx}" kv="${num(spinI / dt_s)}" forcelimited="true" forcerange="${num(-servo.spin_Nm)} ${num(servo.spin_Nm)}"/>
<velocity name="steer${sfx}" joint="steer${sfx}" kv="${num(steerI / dt_s)}" forcelimited="true" forcerange="${num(-servo.steer_Nm)} ${num(servo.steer_Nm)}"/>`).join('\n')
    + brakesXml(servo.rear_brake_Nm, spinI, dt_s);
  return `<mujoco model="liftcheck ${fronts.length === 1 ? 'tricycle' : 'four-wheel car'}">
${option(dt_s, gravity_W, knob)}
<worldbody>
<geom name="ground" type="plane" size="0 0 1" condim="3" friction="${num(mu)} 0.005 0.0001" contype="2" conaffinity="1"/>
<body name="chassis" pos="${num(q0.x_m)} ${num(q0.y_m)} ${num(R)}" quat="${num(qw)} 0 0 ${num(qz)}">
  <freejoint name="chassis"/>
  <geom type="box" pos="${num(-l / 2)} 0 0" size="${num(l / 2)} ${num(w / 2)} ${num(d.chassis_height_m / 2)}" mass="${num(d.chassis_mass_kg)}" contype="0" conaffinity="0"/>
${knuckles}
  <body name="rear_left" pos="${num(-l)} ${num(w / 2)} 0"><joint name="rear_left" type="hinge" axis="0 1 0"/>${wheel}</body>
  <body name="rear_right" pos="${num(-l)} ${num(-w / 2)} 0"><joint name="rear_right" type="hinge" axis="0 1 0"/>${wheel}</body>
</body>
</worldbody>
<actuator>
${actuators}
</actuator>
</mujoco>
`;
}

function buildCar(req) {
  car = disks = null;  // a build that fails leaves no world to step
  const knob = C.applySettings(KNOBS, req.settings, 'car');
  const r = C.carRequest(req);
  const id = compile(carXml(r, knob));
  const { m } = sim;
  const fronts = C.frontWheels(r.car, r.q0.beta_rad).map((f, k, all) => {
    const sfx = all.length === 1 ? '' : ['_left', '_right'][k];
    return { beta0: f.beta0_rad, body: id('body', `front${sfx}`), spin_q: m.jnt_qposadr[id('joint', `spin${sfx}`)],
      steer_q: m.jnt_qposadr[id('joint', `steer${sfx}`)], spin_a: id('actuator', `spin${sfx}`), steer_a: id('actuator', `steer${sfx}`) };
  });
  const brakes = r.servo.rear_brake_Nm > 0 ? ['rear_left', 'rear_right'].map((n) => id('actuator', `brake_${n}`)) : [];
  car = { dt_s: r.dt_s, ground: id('geom', 'ground'), chassis: id('body', 'chassis'), fronts, rears: ['rear_left', 'rear_right'].map((n) => id('body', n)), brakes };
  return carState(0);
}

const forceBuf = new mj.DoubleBuffer(6);  // mj_contactForce's six numbers, reused

const at3 = (a, i) => [a[3 * i], a[3 * i + 1], a[3 * i + 2]];

/// Body b's state from MuJoCo's own: position and orientation (xpos, xquat), and the velocity of
/// its centre of mass from cvel (angular, then linear at the subtree's centre of mass), as
/// mj_objectVelocity computes it: v = v_com + w x (xipos - subtree_com[root]).
function bodyState(b) {
  const { m, d } = sim;
  const cvel = d.cvel, root = m.body_rootid[b];
  const w = [cvel[6 * b], cvel[6 * b + 1], cvel[6 * b + 2]], v0 = [cvel[6 * b + 3], cvel[6 * b + 4], cvel[6 * b + 5]];
  const xi = at3(d.xipos, b), sc = at3(d.subtree_com, root), r = [xi[0] - sc[0], xi[1] - sc[1], xi[2] - sc[2]];
  const v = [v0[0] + w[1] * r[2] - w[2] * r[1], v0[1] + w[2] * r[0] - w[0] * r[2], v0[2] + w[0] * r[1] - w[1] * r[0]];
  const q = d.xquat;  // [w, x, y, z]
  return { p: at3(d.xpos, b), q: [q[4 * b + 1], q[4 * b + 2], q[4 * b + 3], q[4 * b]], v, w };
}

function carState(engine_s) {
  const { d } = sim;
  const chassis = bodyState(car.chassis);
  // The hinges' own coordinates: spin relative to the knuckle; steering from beta0, where the
  // knuckle is built (the joint's zero).
  const { fronts, rears } = car;
  return C.carReply(engine_s, fronts.map((f) => d.qpos[f.spin_q]), fronts.map((f) => f.beta0 + d.qpos[f.steer_q]), chassis.q,
    fronts.map((f) => bodyState(f.body)), rears.map(bodyState));
}

function stepCar(req) {
  const { spin, steer, dt_s } = C.carStep(req);
  const { m, d } = sim;
  timestep(dt_s);
  car.fronts.forEach((f, k) => {
    d.ctrl[f.spin_a] = spin[k];
    d.ctrl[f.steer_a] = steer[k];
  });
  for (const a of car.brakes) d.ctrl[a] = 0;  // a braked run's rear wheels: zero speed relative to the chassis
  let engine_s = timed(() => mj.mj_step2(m, d));
  const ground_force_W = groundForce();  // the step just solved: its contacts and efc_force
  engine_s += timed(() => mj.mj_step1(m, d));
  check();
  return { ...carState(engine_s), ground_force_W, v_chassis_W: bodyState(car.chassis).v };
}

/// The force the ground plane's contacts exerted on the wheels in the step just solved, world
/// frame, N: mj_contactForce gives the normal and tangential components in the contact frame,
/// whose first row is the normal from geom1 towards geom2, the force acting on geom2 (as the
/// compiled-in adapter reads it).
function groundForce() {
  const { m, d } = sim;
  const sum = [0, 0, 0];
  const contacts = d.contact;  // a copy of d->contact made at each reading: read once a step
  try {
    for (let i = 0; i < d.ncon; i++) {
      const c = contacts.get(i);
      if (c.geom1 === car.ground || c.geom2 === car.ground) {
        mj.mj_contactForce(m, d, i, forceBuf);
        const f = forceBuf.GetView(), fr = c.frame, sign = c.geom2 === car.ground ? -1 : 1;
        for (let k = 0; k < 3; k++) sum[k] += sign * (f[0] * fr[k] + f[1] * fr[3 + k] + f[2] * fr[6 + k]);
      }
      c.delete?.();
    }
  } finally {
    contacts.delete?.();
  }
  return sum;
}

function disksXml({ radius_m, dt_s, cM0, cN0, mu_MN }, knob) {
  const r = num(radius_m);
  // Frictionless (condim 1) in every scenario; with friction mu_MN, condim 3 (MuJoCo takes the larger of the two geoms').
  const contact = `condim="${mu_MN > 0 ? 3 : 1}" friction="${num(mu_MN)} 0 0"`;
  return `<mujoco model="liftcheck disks">
${option(dt_s, [0, 0, 0], { impratio: CONFIG.impratio, ...knob })}
<worldbody>
<body name="M" pos="${num(cM0[0])} ${num(cM0[1])} 0">
  <joint name="x" type="slide" axis="1 0 0"/><joint name="y" type="slide" axis="0 1 0"/>
  <geom type="sphere" size="${r}" mass="1" ${contact}/>
</body>
<body name="N" mocap="true" pos="${num(cN0[0])} ${num(cN0[1])} 0"><geom type="sphere" size="${r}" ${contact}/></body>
</worldbody>
<actuator><velocity name="x" joint="x" kv="${num(1 / dt_s)}"/><velocity name="y" joint="y" kv="${num(1 / dt_s)}"/></actuator>
</mujoco>
`;
}

function buildDisks(req) {
  car = disks = null;
  const knob = C.applySettings(KNOBS, req.settings, 'disks');
  const r = C.diskRequest(req);
  const id = compile(disksXml(r, knob));
  const { m } = sim;
  const M = id('body', 'M'), N = id('body', 'N');
  disks = { dt_s: r.dt_s, M, N, mocap: m.body_mocapid[N], gM: m.body_geomadr[M], gN: m.body_geomadr[N], ax: id('actuator', 'x'), ay: id('actuator', 'y') };
  car = null;
  return diskPositions();
}

function diskPositions() {
  const x = sim.d.xpos, w = sim.d.cvel;  // cvel: [rotation; translation] per body, the rotation in the world frame
  return { cM: [x[3 * disks.M], x[3 * disks.M + 1]], cN: [x[3 * disks.N], x[3 * disks.N + 1]], wM: [w[6 * disks.M], w[6 * disks.M + 1], w[6 * disks.M + 2]] };
}

/// The M-N contacts mj_step1 generated on the state the coming step starts from.
function diskContacts() {
  const { d } = sim;
  const c = { count: 0, depth_max_m: 0, distance_min_m: 0 };
  let dmin = Infinity;
  const contacts = d.ncon > 0 ? d.contact : null;  // a copy made at each reading: read once
  for (let i = 0; i < d.ncon; i++) {
    const k = contacts.get(i);
    const pair = (k.geom1 === disks.gM && k.geom2 === disks.gN) || (k.geom1 === disks.gN && k.geom2 === disks.gM);
    if (pair) {
      c.count += 1;
      dmin = Math.min(dmin, k.dist);
    }
    k.delete?.();
  }
  contacts?.delete?.();
  if (c.count > 0) Object.assign(c, { distance_min_m: dmin, depth_max_m: Math.max(0, -dmin) });
  return c;
}

function stepDisks(req) {
  const { vM, cN_next, dt_s } = C.diskStep(req);
  const { m, d } = sim;
  timestep(dt_s);
  const contacts = diskContacts();
  d.ctrl[disks.ax] = vM[0];
  d.ctrl[disks.ay] = vM[1];
  let engine_s = timed(() => mj.mj_step2(m, d));
  const mp = d.mocap_pos;  // N is placed on its path, then the new state's kinematics and contacts
  mp[3 * disks.mocap] = cN_next[0];
  mp[3 * disks.mocap + 1] = cN_next[1];
  mp[3 * disks.mocap + 2] = 0;
  engine_s += timed(() => mj.mj_step1(m, d));
  check();
  return { engine_s, ...diskPositions(), contacts };
}

serve({
  hello: () => ({
    engine: 'MuJoCo', version: mj.mj_versionString(), precision: 'float64', vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: KNOBS,
    fixed: [
      ['model', `the MJCF of liftcheck's compiled-in ${CONFIG.stiff ? 'mujoco-stiff' : 'mujoco'} configuration, compiled by MjModel.loadFromXML from the module's in-memory file system`],
      ['stepping', CONFIG.stiff
        ? 'mj_step1 / set ctrl / mj_step2 (equal to mj_step); Euler, Newton solver, 100 iterations, tolerance 1e-8 (defaults), elliptic cone, impratio 10 (car: knob impratio; disks 10), noslip off'
        : 'mj_step1 / set ctrl / mj_step2 (equal to mj_step); MuJoCo\'s defaults: Euler, Newton solver, 100 iterations, tolerance 1e-8, pyramidal cone, impratio 1, noslip off'],
      ['contact', CONFIG.stiff
        ? 'every geom solref (2 dt, 1): the time constant at its refsafe floor of 2 x timestep, damping ratio 1; solimp 0.9 0.95 0.001 (default), margin 0'
        : 'solref (solref_timeconst_s, 1): the geom defaults\' time constant, --set solref_timeconst_s for cars and disks (default 0.02 s, MuJoCo\'s; refused below 2 dt, refsafe\'s floor); solimp 0.9 0.95 0.001 (default), margin 0; car --set cone (default pyramidal, MuJoCo\'s; elliptic)'],
      ['joints', 'free-joint chassis at the front-axle centre (box l/2 behind it, no collision); knuckle hinged about the chassis z (inertia m x 2e-3 m^2); front wheel hinged about the knuckle y; rear wheels hinged about the chassis y; four wheels: two knuckles at (0, +-track/2), each at its Ackermann angle'],
      ['actuators', 'velocity actuators on spin and steering, kv = the joint\'s own inertia / dt, forcerange the request\'s torque limit'],
      ['friction', 'wheels and ground friction mu (MuJoCo takes the larger of the two geoms\'), condim 3'],
      ['contact forces', 'mj_contactForce on every wheel-ground contact of the step just solved (between mj_step2 and mj_step1), turned to the world frame: each step reply\'s ground_force_W, with the chassis\'s centre-of-mass velocity v_chassis_W (the load and momentum checks)'],
      ['disks', 'M sphere 1 kg on slide joints x, y, velocity actuators kv = 1 kg / dt; N mocap sphere placed on cN_next after mj_step2; condim 1, no gravity; contacts: those mj_step1 generated on the state the step starts from'],
    ],
  }),
  car: buildCar,
  disks: buildDisks,
  stepCar,
  stepDisks,
});
