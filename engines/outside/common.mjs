// What every JavaScript adapter shares: checking a request against docs/protocol.md, the knobs a
// configuration declares, the chassis frame (x forward along the tie rod, y left, z up, origin at
// the front-axle centre), quaternions [x, y, z, w], and the car reply assembled from body states
// the adapter read off its engine.

/// The radius of gyration squared (m^2) of the steering knuckle, about every axis: that of the
/// knuckle of liftcheck's compiled-in cars (0.05 kg, 1e-4 kg m^2), scaled to the mass asked for.
export const KNUCKLE_GYRATION_SQ_M2 = 1e-4 / 0.05;
/// The radius of a solid sphere of that gyration (0.4 r^2 = k^2), m: the knuckle of the adapters
/// that give it a shape and let the engine compute its inertia.
export const KNUCKLE_RADIUS_M = Math.sqrt(1e-4 / (0.4 * 0.05));

/// Half-size of a square ground box centred under the start, m: room for the scenarios' drives
/// (10 m paths, laps of the turning circle l / sin(beta)) and no more (float32 engines lose
/// contact precision on large shapes, docs/protocol.md).
export function groundHalf_m(car) {
  return Math.max(30, 10 * car.l_m);
}

export function wrapAngle(a) {
  return a - 2 * Math.PI * Math.floor((a + Math.PI) / (2 * Math.PI));
}

function need(cond, what) {
  if (!cond) throw new Error(what);
}

function positive(obj, key, where) {
  const v = obj?.[key];
  need(typeof v === 'number' && Number.isFinite(v) && v > 0, `${where}.${key} must be a positive number`);
  return v;
}

function finiteNumber(obj, key, where) {
  const v = obj?.[key];
  need(typeof v === 'number' && Number.isFinite(v), `${where}.${key} must be a finite number`);
  return v;
}

function vector(obj, key, n, where) {
  const v = obj?.[key];
  need(Array.isArray(v) && v.length === n && v.every((x) => typeof x === 'number' && Number.isFinite(x)),
    `${where}.${key} must be ${n} finite numbers`);
  return v;
}

/// The knobs of a configuration (hello's `settings`): `specs` as sent in hello, `given` the
/// request's `settings` object of strings. Every knob of `vehicle` from `given` or its default,
/// each checked against its kind (integer, real, choice) and range; an unknown key, a value of
/// the wrong kind or out of range is refused, never clamped.
export function applySettings(specs, given, vehicle) {
  const mine = specs.filter((k) => k.vehicle === vehicle);
  for (const key of Object.keys(given ?? {}))
    need(mine.some((k) => k.key === key), `setting '${key}' is not a ${vehicle} setting of this configuration (it has ${mine.map((k) => k.key).join(', ') || 'none'})`);
  const values = {};
  for (const k of mine) values[k.key] = parseSetting(k, given && Object.hasOwn(given, k.key) ? String(given[k.key]) : k.default);
  return values;
}

function parseSetting(k, text) {
  if (k.kind === 'choice') {
    need(k.choices.includes(text), `setting ${k.key} = '${text}' is not one of ${k.choices.join(' | ')}`);
    return text;
  }
  const v = Number(text);
  const whole = k.kind === 'integer';
  need(text.trim() !== '' && Number.isFinite(v) && (!whole || Number.isInteger(v)), `setting ${k.key} = '${text}' is not ${whole ? 'a whole number' : 'a number'}`);
  need((k.min_exclusive ? v > k.min : v >= k.min) && v <= k.max, `setting ${k.key} = ${text} is outside ${k.min_exclusive ? '(' : '['}${k.min}, ${k.max}]`);
  return v;
}

/// The wheel-shape knob of the adapters that build cylinder wheels too (Bullet's `wheel`, same choices).
export const WHEEL_KNOB = { key: 'wheel', vehicle: 'car', kind: 'choice', choices: ['sphere', 'cylinder'], default: 'sphere',
  help: 'wheel collision shape: spheres of radius R, or cylinders of wheel_width_m about the axle' };

/// The wheel shape a car request asks for: the `wheel` knob (its value in `knobs`) where it is
/// set, else car.wheel_shape (the two must agree where both are given).
export function wheelShapeOf(req, knobs) {
  const given = req.settings && Object.hasOwn(req.settings, 'wheel');
  need(!given || req.car.wheel_shape === undefined || req.car.wheel_shape === knobs.wheel,
    `setting wheel = ${knobs.wheel} disagrees with car.wheel_shape = ${req.car.wheel_shape}`);
  return given ? knobs.wheel : req.car.wheel_shape;
}

/// The car request's numbers, checked: the tricycle (wheels 3) or the four-wheel car, with wheels
/// of one of `shapes` (the wheel_shape given, sphere where none is).
export function carRequest(req, shapes = ['sphere']) {
  const c = req.car;
  need(c && typeof c === 'object', 'car request without a car object');
  const car = {};
  for (const k of ['R_m', 'l_m', 'track_m', 'wheel_width_m', 'chassis_height_m', 'chassis_mass_kg', 'wheel_mass_kg', 'knuckle_mass_kg'])
    car[k] = positive(c, k, 'car');
  need(c.wheels === 3 || c.wheels === 4, `car.wheels = ${c.wheels}: 3 (the tricycle) or 4`);
  car.wheels = c.wheels;
  car.parallel_steering = c.parallel_steering === true;
  need(shapes.includes(c.wheel_shape ?? 'sphere'), `car.wheel_shape '${c.wheel_shape}': this adapter builds ${shapes.join(' or ')} wheels`);
  const mu = finiteNumber(req, 'mu', 'car request');
  need(mu >= 0, 'mu must not be negative');
  const q0 = {};
  for (const k of ['x_m', 'y_m', 'phi_rad', 'beta_rad']) q0[k] = finiteNumber(req.q0, k, 'q0');
  const servo = { spin_Nm: positive(req.servo, 'spin_torque_max_Nm', 'servo'), steer_Nm: positive(req.servo, 'steer_torque_max_Nm', 'servo') };
  // A braked run (docs/protocol.md; only to an adapter whose hello declares "brakes"): each rear
  // wheel held at zero spin speed by the engine's own joint motor, up to this torque. 0: free.
  servo.rear_brake_Nm = req.servo.rear_brake_torque_max_Nm === undefined ? 0 : positive(req.servo, 'rear_brake_torque_max_Nm', 'servo');
  return { car, q0, servo, mu, dt_s: positive(req, 'dt_s', 'car request'), gravity_W: vector(req, 'gravity_W', 3, 'car request') };
}

/// The front wheels of a car at steering beta0: the tricycle's one at the front-axle centre, or
/// the four-wheel car's left and right at (0, +-track/2), each at its Ackermann angle,
/// cot(beta_s) = cot(beta) - s track/(2 l) with s = +1 left, -1 right (models/ackermann.hpp), or
/// at beta0 itself when steered in parallel. Each: its chassis-frame y and start angle.
export function frontWheels(car, beta0) {
  if (car.wheels === 3) return [{ y_m: 0, beta0_rad: beta0 }];
  const k = car.track_m / (2 * car.l_m);
  return [1, -1].map((s) => ({
    y_m: s * car.track_m / 2,
    beta0_rad: car.parallel_steering ? beta0 : Math.atan2(Math.sin(beta0), Math.cos(beta0) - s * k * Math.sin(beta0)),
  }));
}

export function diskRequest(req) {
  const mu_MN = req?.mu_MN;
  need(typeof mu_MN === 'number' && Number.isFinite(mu_MN) && mu_MN >= 0, 'disks request.mu_MN must be a number >= 0');
  return { radius_m: positive(req, 'radius_m', 'disks request'), dt_s: positive(req, 'dt_s', 'disks request'),
    cM0: vector(req, 'cM0', 2, 'disks request'), cN0: vector(req, 'cN0', 2, 'disks request'), mu_MN };
}

/// A step request's rates (car) or commands (disks), checked.
export function carStep(req) {
  return { spin: vector(req, 'spin_radps', 2, 'step'), steer: vector(req, 'steer_radps', 2, 'step'), dt_s: positive(req, 'dt_s', 'step') };
}
export function diskStep(req) {
  return { vM: vector(req, 'vM_cmd', 2, 'step'), cN_next: vector(req, 'cN_next', 2, 'step'), vN: vector(req, 'vN', 2, 'step'), dt_s: positive(req, 'dt_s', 'step') };
}

/// A point (bx, by, bz) of the chassis frame of a car placed at q0, in world coordinates.
export function chassisPoint(q0, bx, by, bz) {
  const c = Math.cos(q0.phi_rad), s = Math.sin(q0.phi_rad);
  return [q0.x_m + c * bx - s * by, q0.y_m + s * bx + c * by, bz];
}

export function yawQuat(psi) {
  return [0, 0, Math.sin(0.5 * psi), Math.cos(0.5 * psi)];
}

/// v rotated by the unit quaternion q = [x, y, z, w].
export function rotate(q, v) {
  const [x, y, z, w] = q;
  const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
}

/// The heading of a body: the angle of its x axis about the world z.
export function heading(q) {
  const [x, y, z, w] = q;
  return Math.atan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z));
}

/// Angle of body b relative to body a about a's local axis (0 = x, 1 = y, 2 = z): the twist
/// of the relative rotation conj(qa) qb about that axis (swing-twist decomposition).
export function twist(qa, qb, axis) {
  const [ax, ay, az, aw] = qa, [bx, by, bz, bw] = qb;
  // r = conj(a) * b
  const rw = aw * bw + ax * bx + ay * by + az * bz;
  const rx = aw * bx - ax * bw - ay * bz + az * by;
  const ry = aw * by + ax * bz - ay * bw - az * bx;
  const rz = aw * bz - ax * by + ay * bx - az * bw;
  return wrapAngle(2 * Math.atan2([rx, ry, rz][axis], rw));
}

export function sphereInertia(m, r) {
  const i = 0.4 * m * r * r;
  return [i, i, i];
}

export function boxInertia(m, hx, hy, hz) {
  return [(m / 3) * (hy * hy + hz * hz), (m / 3) * (hx * hx + hz * hz), (m / 3) * (hx * hx + hy * hy)];
}

/// One wheel's entry of the reply from its body state: position p, orientation q (its local y is
/// the axle), linear velocity v and angular velocity w of its centre, world frame.
export function wheelState(p, q, v, w) {
  return { v_hub_W: [...v], omega_W: [...w], axle_W: rotate(q, [0, 1, 0]), hub_z_m: p[2] };
}

/// The car reply (RigidCarState): each front wheel's spin and steering angle, the chassis
/// orientation, the front wheels' and then the rear wheels' (left, right) body states {p, q, v, w}.
export function carReply(engine_s, spin_rad, steer_rad, chassis_q, fronts, rears) {
  const pad = (a) => (a.length === 2 ? a : [a[0], 0]);
  const n = fronts.length;
  return {
    engine_s, spin_joint_rad: pad(spin_rad.map(wrapAngle)), steer_rad: pad(steer_rad),
    x_m: fronts.reduce((x, b) => x + b.p[0] / n, 0), y_m: fronts.reduce((y, b) => y + b.p[1] / n, 0),
    z_m: Math.min(...fronts.map((b) => b.p[2])), phi_rad: heading(chassis_q), rear_z_m: Math.min(...rears.map((b) => b.p[2])),
    wheels: [...fronts, ...rears].map((b) => wheelState(b.p, b.q, b.v, b.w)),
  };
}

/// The command-line options every adapter takes: --config NAME (one of `configs`), --fault F.
export function parseArgs(argv, configs, faults = []) {
  const opts = { config: null, fault: null };
  for (let i = 0; i < argv.length; i += 2) {
    const [flag, value] = [argv[i], argv[i + 1]];
    if (flag === '--config' && value in configs) opts.config = value;
    else if (flag === '--fault' && faults.includes(value)) opts.fault = value;
    else {
      console.error(`usage: --config ${Object.keys(configs).join('|')}${faults.length ? ` [--fault ${faults.join('|')}]` : ''} (got '${flag} ${value ?? ''}')`);
      process.exit(2);
    }
  }
  if (!opts.config) {
    console.error(`--config ${Object.keys(configs).join('|')} is required`);
    process.exit(2);
  }
  return opts;
}

/// The step reply's contacts from a tally {count, distance_min_m} of the step's M-N contact points
/// (distance_min_m the smallest signed distance, negative when penetrating; Infinity before any).
export function contactsReply(c) {
  return c.count > 0
    ? { count: c.count, depth_max_m: Math.max(0, -c.distance_min_m), distance_min_m: c.distance_min_m }
    : { count: 0, depth_max_m: 0, distance_min_m: 0 };
}
