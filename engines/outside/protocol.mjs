// The liftcheck engine protocol (docs/protocol.md), version 3: one JSON request per line on
// standard input, one JSON reply per line on standard output, each reply carrying its request's
// number ("id"; this loop puts it in, the adapter never sees it). An adapter supplies an object with
// hello(), car(request), disks(request), stepCar(request) and stepDisks(request) (or one
// step(request) of its own); this loop does the framing, steps whichever world the last build
// made (none after a build that failed), and the error replies. Everything the adapter logs goes to standard error.
//
// Per step it costs one blocking read of standard input (no event loop, no line interface), one
// JSON.parse, one JSON.stringify and one write; the reply is searched for non-finite numbers only when its text
// has a null in it (JSON.stringify writes NaN and Infinity as null).
import { readSync, writeSync } from 'node:fs';
import { StringDecoder } from 'node:string_decoder';

export const PROTOCOL = 3;

function finite(value, where) {
  if (typeof value === 'number' && !Number.isFinite(value)) throw new Error(`${where} is not finite`);
  if (Array.isArray(value)) value.forEach((v, i) => finite(v, `${where}[${i}]`));
  else if (value && typeof value === 'object') for (const [k, v] of Object.entries(value)) finite(v, `${where}.${k}`);
}

/// One reply line written whole (standard output is a pipe: a synchronous write on Linux).
function out(text) {
  const bytes = Buffer.from(text + '\n');
  for (let done = 0; done < bytes.length;) {
    try {
      done += writeSync(1, bytes, done);
    } catch (e) {
      if (e.code !== 'EAGAIN') throw e;
    }
  }
}

/// The request's number as it goes into its reply: `"id":N,` (nothing for a request without one).
function idField(req) {
  return req && Number.isSafeInteger(req.id) ? `"id":${req.id},` : '';
}

/// The reply {ok: true, id, ...reply} as text, refused if it holds a non-finite number.
function okText(reply, req) {
  const text = JSON.stringify(reply);
  if (text.includes('null')) finite(reply, 'reply');
  const head = `{"ok":true,${idField(req)}`;
  return text === '{}' ? `${head.slice(0, -1)}}` : `${head}${text.slice(1)}`;
}

/// The reply {ok: false, id, error} as text: the message's first line.
function errorText(message, req) {
  return `{"ok":false,${idField(req)}"error":${JSON.stringify(message.split('\n')[0])}}`;
}

/// The lines of standard input, read with blocking reads of fd 0 as large as the pipe gives them
/// (no event loop turn between a request and its reply). fd 0 is never handed to process.stdin,
/// so it stays as the parent made it; a non-blocking one (EAGAIN) is waited on in 1 ms sleeps.
function* lines() {
  const buf = Buffer.allocUnsafe(1 << 16);
  const nap = new Int32Array(new SharedArrayBuffer(4));
  const utf8 = new StringDecoder('utf8');  // a character split between two reads is joined
  let rest = '';
  for (;;) {
    let got;
    try {
      got = readSync(0, buf, 0, buf.length, null);
    } catch (e) {
      if (e.code === 'EAGAIN') { Atomics.wait(nap, 0, 0, 1); continue; }
      if (e.code === 'EOF') break;
      throw e;
    }
    if (got === 0) break;
    rest += utf8.write(buf.subarray(0, got));
    let nl;
    while ((nl = rest.indexOf('\n')) >= 0) {
      const line = rest.slice(0, nl);
      rest = rest.slice(nl + 1);
      yield line.endsWith('\r') ? line.slice(0, -1) : line;
    }
  }
  rest += utf8.end();
  if (rest) yield rest;
}

/// The world the last build made: 'car', 'disks', or null before any and after one that failed.
let built = null;

async function answer(adapter, req) {
  switch (req.op) {
    case 'hello':
      if (req.protocol !== PROTOCOL) throw new Error(`protocol ${req.protocol} asked, this adapter speaks ${PROTOCOL}`);
      // "steps" is this loop's (servoSteps): offered for an adapter whose car steps go through it.
      return { protocol: PROTOCOL, ...(await adapter.hello()), servo_steps: servoStepsOffered(adapter) };
    case 'car':
    case 'disks': {
      built = null;
      const reply = await adapter[req.op](req);
      built = req.op;
      return reply;
    }
    default: throw new Error(`unknown op '${req.op}'`);
  }
}

function step(adapter, req) {
  if (adapter.step) return adapter.step(req);  // an adapter that dispatches its steps itself
  if (!built) throw new Error('step before any car or disks build');
  if (!(req.dt_s > 0)) throw new Error('step needs dt_s > 0');
  return built === 'car' ? adapter.stepCar(req) : adapter.stepDisks(req);
}

/// Offered unless the adapter dispatches its own steps or LIFTCHECK_SERVO_STEPS=0 (the tests that
/// compare a planned run with one stepped a request at a time).
function servoStepsOffered(adapter) {
  return !adapter.step && typeof adapter.stepCar === 'function' && process.env.LIFTCHECK_SERVO_STEPS !== '0';
}

/// liftcheck's e2::wrap_angle (models/e2.cpp), operation for operation: JavaScript's % on doubles
/// is C's fmod, exact, so the wheel angle booked here is the one liftcheck books.
function wrapAsLiftcheck(a) {
  const twoPi = 2.0 * Math.PI;
  let r = (a + Math.PI) % twoPi;
  if (r <= 0.0) r += twoPi;
  return r - Math.PI;
}

function number(req, key) {
  const v = req[key];
  if (typeof v !== 'number' || !Number.isFinite(v)) throw new Error(`steps needs a finite number ${key}`);
  return v;
}

/// "steps" (docs/protocol.md): the tricycle's next steps under liftcheck's servo law, as
/// RigidCar::drive (engines/rigid_car.cpp) applies it for one front wheel: before each step, spin
/// rate = alpha_rate + spin_gain (alpha - alpha_booked) and steering rate = beta_rate + steer_gain
/// (beta - steering angle); after it, alpha_booked += wrap(spin angle - the previous one). Each
/// step's reply is a line of its own, with the rates applied ("applied": [spin, steering]), which
/// liftcheck checks against its own; a step that fails ends the lines with its error.
function servoSteps(adapter, req) {
  if (built !== 'car') throw new Error('steps before a car is built');
  const dt_s = number(req, 'dt_s'), ka = number(req, 'spin_gain_per_s'), kb = number(req, 'steer_gain_per_s');
  let alpha = number(req, 'alpha_rad'), spin = number(req, 'spin_rad'), steer = number(req, 'steer_rad');
  if (!Array.isArray(req.targets) || req.targets.length === 0) throw new Error('steps needs targets');
  const lines = [];
  for (const g of req.targets) {
    try {
      if (!Array.isArray(g) || g.length !== 4 || !g.every(Number.isFinite)) throw new Error('a steps target must be 4 finite numbers');
      const [ta, tb, ra, rb] = g;
      const applied = [ra + ka * (ta - alpha), rb + kb * (tb - steer)];
      const reply = adapter.stepCar({ op: 'step', spin_radps: [applied[0], 0], steer_radps: [applied[1], 0], dt_s });
      lines.push(okText({ ...reply, applied }, req));
      const [spin1] = reply.spin_joint_rad ?? [], [steer1] = reply.steer_rad ?? [];
      if (!Number.isFinite(spin1) || !Number.isFinite(steer1)) break;  // liftcheck names what the reply lacks
      alpha += wrapAsLiftcheck(spin1 - spin);
      spin = spin1 + 0;  // as liftcheck reads them: the reply's text has no -0
      steer = steer1 + 0;
    } catch (e) {
      lines.push(errorText(String(e && e.message ? e.message : e), req));
      break;
    }
  }
  return lines.join('\n');
}

export async function serve(adapter) {
  console.log = console.error;  // keep standard output for replies only
  for (const line of lines()) {
    let req;
    try {
      req = JSON.parse(line);
    } catch (e) {
      out(errorText(`request is not JSON: ${e.message}`, null));
      continue;
    }
    try {
      if (req.op === 'bye') {
        out(okText({}, req));
        process.exit(0);
      }
      // A step is answered without an await: no turn of the event loop between request and reply.
      if (req.op === 'steps' && servoStepsOffered(adapter)) out(servoSteps(adapter, req));
      else out(okText(req.op === 'step' ? step(adapter, req) : await answer(adapter, req), req));
    } catch (e) {
      out(errorText(String(e && e.message ? e.message : e), req));
    }
  }
}

/// Seconds spent in fn(), for the reply's engine_s (the engine's own stepping time).
export function timed(fn) {
  const t0 = process.hrtime.bigint();
  fn();
  return Number(process.hrtime.bigint() - t0) * 1e-9;
}
