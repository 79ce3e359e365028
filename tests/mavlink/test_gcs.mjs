// tern's MAVLink endpoint (core/apps/mavlink, docs/ground-station.md) against an independent
// implementation: node-mavlink (its own splitter, CRCs with the CRC_EXTRA of its own common
// dialect, and message classes) plays the ground station, over loopback, as QGroundControl would.
//
//   node test_gcs.mjs TERN MISSION WORK_DIR
//
// It binds a free UDP port as the GCS, flies MISSION with `tern fly --realtime --gcs 127.0.0.1:PORT
// --gcs-bind 127.0.0.1:0`, waits for the first HEARTBEAT (no sleeping), then checks:
//   - HEARTBEAT (MAV_TYPE_FIXED_WING, MAV_AUTOPILOT_GENERIC, armed, custom_mode a tern phase),
//     SYS_STATUS, ATTITUDE, GLOBAL_POSITION_INT, VFR_HUD, GPS_RAW_INT, HOME_POSITION and a
//     STATUSTEXT arrive, every frame with a CRC node-mavlink accepts; values plausible;
//   - PARAM_REQUEST_LIST: param_count PARAM_VALUEs, indices 0..count-1 once each, count equal to
//     the numeric and boolean parameters `tern params` lists, each id and type where
//     `tern params --mavlink` puts it;
//   - PARAM_SET slc.course_kp 2.5 answered with PARAM_VALUE 2.5, read back by PARAM_REQUEST_READ
//     (by id and by index); a start-only parameter (sim.init_altitude, by its shortened id as
//     `tern params --mavlink` lists it) refused with its old value and a STATUSTEXT;
//   - hostile datagrams (random bytes, a wrong CRC, truncated frames, an unknown message id) are
//     counted in SYS_STATUS.errors_comm and the endpoint still answers;
//   - the flight's params.csv records the change with source "mavlink".
// Exit 0 when all hold; 1 with one line per failure.
import { spawn, execFileSync } from 'node:child_process'
import dgram from 'node:dgram'
import fs from 'node:fs'
import path from 'node:path'
import { Readable } from 'node:stream'
import { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } from 'node-mavlink'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
fs.mkdirSync(work, { recursive: true })
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }
const failures = []
const check = (ok, what) => {
  if (!ok) failures.push(what)
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`)
}

// ---- the GCS socket and node-mavlink's reader ----
const sock = dgram.createSocket('udp4')
await new Promise((resolve) => sock.bind(0, '127.0.0.1', resolve))
const gcsPort = sock.address().port
const input = new Readable({ read() {} })
let crcErrors = 0
const reader = input
  .pipe(new MavLinkPacketSplitter({}, { onCrcError: () => crcErrors++ }))
  .pipe(new MavLinkPacketParser())
let vehicle = null // where the vehicle's packets come from
sock.on('message', (buf, rinfo) => {
  if (!vehicle) vehicle = { address: rinfo.address, port: rinfo.port }
  input.push(buf)
})
const waiters = []
const seen = {} // message class name -> count
const last = {} // message class name -> latest data
const texts = []
reader.on('data', (packet) => {
  const clazz = REGISTRY[packet.header.msgid]
  if (!clazz) return
  const data = packet.protocol.data(packet.payload, clazz)
  const name = clazz.MSG_NAME
  seen[name] = (seen[name] || 0) + 1
  last[name] = { header: packet.header, data }
  if (name === 'STATUSTEXT') texts.push(data.text)
  for (const w of [...waiters]) {
    if (w.name === name && w.match(data)) {
      waiters.splice(waiters.indexOf(w), 1)
      clearTimeout(w.timer)
      w.resolve(data)
    }
  }
})
/** The next message `name` for which match(data) holds, within `ms` of wall time. */
function next(name, match = () => true, ms = 10000) {
  return new Promise((resolve, reject) => {
    const w = { name, match, resolve }
    w.timer = setTimeout(() => {
      waiters.splice(waiters.indexOf(w), 1)
      reject(new Error(`no ${name} within ${ms} ms`))
    }, ms)
    waiters.push(w)
  })
}
const protocol = new MavLinkProtocolV2(255, 190) // a GCS: system 255, MAV_COMP_ID_MISSIONPLANNER
let seq = 0
function send(msg) {
  sock.send(protocol.serialize(msg, seq++ & 255), vehicle.port, vehicle.address)
}

// ---- what `tern params` lists: the numeric and boolean parameters are the GCS's ----
const listing = execFileSync(tern, ['params', mission], { encoding: 'utf8' })
// and the ids tern documents for them (`tern params --mavlink`: index, id, type, name)
const table = execFileSync(tern, ['params', mission, '--mavlink'], { encoding: 'utf8' })
  .split('\n').map((l) => l.trim().split(/\s+/)).filter((r) => r.length === 4 && /^\d+$/.test(r[0]))
  .map(([index, id, type, name]) => ({ index: Number(index), id, type, name }))
const idOf = (name) => (table.find((r) => r.name === name) || {}).id

// ---- fly ----
const logDir = path.join(work, 'runs')
const child = spawn(tern, ['fly', mission, '--realtime', '--duration', '40', '--log-dir', logDir, '-q',
  '--gcs', `127.0.0.1:${gcsPort}`, '--gcs-bind', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] })
let out = ''
child.stdout.on('data', (d) => { out += d })
const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })))

let status = 0
try {
  const hb = await next('HEARTBEAT', (d) => (d.baseMode & 128) !== 0, 20000) // armed: flying
  check(hb.type === minimal.MavType.FIXED_WING, `HEARTBEAT type ${hb.type} is MAV_TYPE_FIXED_WING`)
  check(hb.autopilot === minimal.MavAutopilot.GENERIC, `HEARTBEAT autopilot ${hb.autopilot} is MAV_AUTOPILOT_GENERIC`)
  check(hb.mavlinkVersion === 3, `HEARTBEAT mavlink_version ${hb.mavlinkVersion}`)
  check((hb.baseMode & 1) !== 0 && hb.customMode <= 9, `HEARTBEAT custom mode ${hb.customMode} is a tern phase`)
  check(hb.systemStatus === minimal.MavState.ACTIVE, `HEARTBEAT system_status ${hb.systemStatus} is MAV_STATE_ACTIVE`)
  const att = await next('ATTITUDE')
  check([att.roll, att.pitch, att.yaw].every((a) => Number.isFinite(a) && Math.abs(a) <= Math.PI + 1e-6), `ATTITUDE roll ${att.roll.toFixed(3)} pitch ${att.pitch.toFixed(3)} yaw ${att.yaw.toFixed(3)} rad`)
  const pos = await next('GLOBAL_POSITION_INT')
  check(pos.lat !== 0 && Math.abs(pos.lat) <= 900000000 && Math.abs(pos.lon) <= 1800000000, `GLOBAL_POSITION_INT lat ${pos.lat / 1e7} lon ${pos.lon / 1e7}`)
  // home is the estimate's origin (its first GNSS fix, in the air here): alt = home's + relative_alt
  const home0 = await next('HOME_POSITION', () => true, 5000)
  check(Math.abs(pos.relativeAlt) < 400000 && Math.abs(pos.alt - home0.altitude - pos.relativeAlt) < 1000,
    `GLOBAL_POSITION_INT alt ${pos.alt} mm MSL = home's ${home0.altitude} + relative_alt ${pos.relativeAlt} (within 1 m)`)
  const hud = await next('VFR_HUD')
  check(hud.airspeed > 5 && hud.airspeed < 60, `VFR_HUD airspeed ${hud.airspeed.toFixed(2)} m/s`)
  const gps = await next('GPS_RAW_INT')
  check(gps.fixType === common.GpsFixType.GPS_FIX_TYPE_3D_FIX, `GPS_RAW_INT fix_type ${gps.fixType}`)
  const home = await next('HOME_POSITION', () => true, 5000)
  check(Math.abs(home.latitude - pos.lat) < 100000, `HOME_POSITION lat ${home.latitude / 1e7} near the aircraft`)
  const sys = await next('SYS_STATUS')
  check((sys.onboardControlSensorsPresent & 3) === 3, `SYS_STATUS gyro and accelerometer present (${sys.onboardControlSensorsPresent})`)
  check(texts.some((t) => t.startsWith('phase ')), `STATUSTEXT of the phase (${JSON.stringify(texts.slice(0, 2))})`)
  const nav = await next('NAV_CONTROLLER_OUTPUT')
  check([nav.navRoll, nav.navPitch, nav.altError, nav.aspdError, nav.xtrackError].every(Number.isFinite) &&
    Math.abs(nav.navRoll) <= 60 && Math.abs(nav.altError) < 200 && Math.abs(nav.aspdError) < 30 && Math.abs(nav.xtrackError) < 1000,
  `NAV_CONTROLLER_OUTPUT nav_roll ${nav.navRoll.toFixed(1)} deg, alt_error ${nav.altError.toFixed(1)} m, aspd_error ${nav.aspdError.toFixed(1)} m/s, xtrack ${nav.xtrackError.toFixed(1)} m, wp_dist ${nav.wpDist} m`)
  const cur = await next('MISSION_CURRENT', () => true, 5000)
  check(cur.total > 0 && cur.seq < cur.total && cur.missionState === 3, `MISSION_CURRENT seq ${cur.seq} of ${cur.total}, state ${cur.missionState} (ACTIVE)`)
  const ext = await next('EXTENDED_SYS_STATE', () => true, 5000)
  check([2, 3].includes(ext.landedState), `EXTENDED_SYS_STATE landed_state ${ext.landedState} (IN_AIR or TAKEOFF)`)
  const wind = await next('WIND_COV', () => true, 5000)
  check(Math.hypot(wind.windX, wind.windY) < 30 && Number.isNaN(wind.windZ), `WIND_COV wind ${wind.windX.toFixed(2)} N ${wind.windY.toFixed(2)} E m/s, down NaN`)
  const clock = await next('SYSTEM_TIME', () => true, 5000)
  check(Math.abs(Number(clock.timeUnixUsec) / 1000 - Date.now()) < 10000, `SYSTEM_TIME ${clock.timeUnixUsec} us is this computer's time`)
  const ts1 = 123456789n
  send(Object.assign(new common.TimeSync(), { tc1: 0n, ts1, targetSystem: 1, targetComponent: 1 }))
  const sync = await next('TIMESYNC', (d) => d.ts1 === ts1, 5000)
  check(sync.tc1 > 0n && sync.targetSystem === 255 && sync.targetComponent === 190, `TIMESYNC answered: tc1 ${sync.tc1} ns, to 255/190`)

  // ---- the parameter list ----
  const values = new Map()
  let count = -1
  const done = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`parameter list: ${values.size} of ${count} after 10 s`)), 10000)
    reader.on('data', (packet) => {
      if (packet.header.msgid !== common.ParamValue.MSG_ID) return
      const d = packet.protocol.data(packet.payload, common.ParamValue)
      count = d.paramCount
      values.set(d.paramIndex, d)
      if (values.size === count) {
        clearTimeout(timer)
        resolve()
      }
    })
  })
  const list = new common.ParamRequestList()
  list.targetSystem = 1
  list.targetComponent = 1
  send(list)
  await done
  const ids = new Set([...values.values()].map((v) => v.paramId))
  check(ids.size === count, `PARAM_VALUE: ${count} parameters, ${ids.size} distinct ids, indices 0..${count - 1}`)
  // tern params' numeric and boolean parameters: its rows "instance.name  value ..." whose value is
  // not text ("...") or a vector ([...])
  const numeric = listing.split('\n').filter((l) => /^\S+\.\S+\s+[^"[ ]/.test(l)).length
  check(numeric === count, `param_count ${count} equals tern params' ${numeric} numeric and boolean parameters`)
  const typeCode = { REAL32: common.MavParamType.REAL32, INT32: common.MavParamType.INT32, UINT8: common.MavParamType.UINT8 }
  const mismatched = table.filter((r) => !values.has(r.index) || values.get(r.index).paramId !== r.id || values.get(r.index).paramType !== typeCode[r.type])
  check(table.length === count && mismatched.length === 0, `every id and type at its index as \`tern params --mavlink\` lists it (${mismatched.length} differ, e.g. ${JSON.stringify(mismatched[0])})`)
  const course = [...values.values()].find((v) => v.paramId === 'slc.course_kp')
  check(course && course.paramType === common.MavParamType.REAL32, `slc.course_kp listed as MAV_PARAM_TYPE_REAL32 (${course && course.paramValue})`)

  // ---- set one, read it back ----
  const set = new common.ParamSet()
  set.targetSystem = 1
  set.targetComponent = 1
  set.paramId = 'slc.course_kp'
  set.paramValue = 2.5
  set.paramType = common.MavParamType.REAL32
  const answer = next('PARAM_VALUE', (d) => d.paramId === 'slc.course_kp')
  send(set)
  const a = await answer
  check(a.paramValue === 2.5, `PARAM_SET slc.course_kp 2.5 answered ${a.paramValue}`)
  const read = new common.ParamRequestRead()
  read.targetSystem = 1
  read.targetComponent = 1
  read.paramId = 'slc.course_kp'
  read.paramIndex = -1
  const back = next('PARAM_VALUE', (d) => d.paramId === 'slc.course_kp')
  send(read)
  const b = await back
  check(b.paramValue === 2.5 && b.paramIndex === course.paramIndex && b.paramCount === count, `PARAM_REQUEST_READ by id: ${b.paramValue} at index ${b.paramIndex}`)
  const byIndex = new common.ParamRequestRead()
  byIndex.targetSystem = 1
  byIndex.targetComponent = 1
  byIndex.paramId = ''
  byIndex.paramIndex = course.paramIndex
  const c = next('PARAM_VALUE', (d) => d.paramIndex === course.paramIndex)
  send(byIndex)
  check((await c).paramValue === 2.5, 'PARAM_REQUEST_READ by index reads 2.5')

  // ---- a start-only parameter is refused in flight, its old value echoed ----
  const altId = idOf('sim.init_altitude') // 17 characters: shortened
  const alt = [...values.values()].find((v) => v.paramId === altId)
  check(alt !== undefined && altId.length === 16 && altId.startsWith('sim.init_al~'), `sim.init_altitude listed as ${altId}`)
  if (alt) {
    const refuse = new common.ParamSet()
    refuse.targetSystem = 1
    refuse.targetComponent = 1
    refuse.paramId = altId
    refuse.paramValue = 250
    refuse.paramType = common.MavParamType.REAL32
    const why = next('STATUSTEXT', (d) => d.text.includes('sim.init_altitude'))
    const echo = next('PARAM_VALUE', (d) => d.paramId === altId)
    send(refuse)
    const e = await echo
    check(e.paramValue === alt.paramValue, `start-only sim.init_altitude refused in flight: ${e.paramValue} kept`)
    const w = await why
    check(w.severity === common.MavSeverity.WARNING, `STATUSTEXT (MAV_SEVERITY_WARNING) says why: ${w.text}`)
  }

  // ---- hostile datagrams ----
  const good = protocol.serialize(read, 200)
  const badCrc = Buffer.from(good)
  badCrc[badCrc.length - 1] ^= 0x5a
  const unknown = Buffer.from(good)
  unknown[7] = 0x99
  for (let i = 0; i < 500; i++) {
    const junk = Buffer.alloc(1 + Math.floor(Math.random() * 280))
    for (let k = 0; k < junk.length; k++) junk[k] = Math.floor(Math.random() * 256)
    if (i % 2 === 0) junk[0] = 0xfd
    sock.send(junk, vehicle.port, vehicle.address)
    if (i % 50 === 0) {
      sock.send(badCrc, vehicle.port, vehicle.address)
      sock.send(good.subarray(0, good.length - 4), vehicle.port, vehicle.address)
      sock.send(unknown, vehicle.port, vehicle.address)
    }
  }
  const after = await next('SYS_STATUS', (d) => d.errorsComm >= 30, 5000)
  check(after.errorsComm >= 30 && after.dropRateComm > 0, `SYS_STATUS after the flood: errors_comm ${after.errorsComm}, drop_rate_comm ${after.dropRateComm} c%`)
  const still = next('PARAM_VALUE', (d) => d.paramId === 'slc.course_kp')
  send(read)
  check((await still).paramValue === 2.5, 'the endpoint still answers after the flood')
  check(crcErrors === 0, `node-mavlink found ${crcErrors} CRC errors in tern's frames`)
  check(['HEARTBEAT', 'SYS_STATUS', 'ATTITUDE', 'GLOBAL_POSITION_INT', 'VFR_HUD', 'GPS_RAW_INT', 'HOME_POSITION', 'PARAM_VALUE', 'STATUSTEXT',
    'NAV_CONTROLLER_OUTPUT', 'MISSION_CURRENT', 'EXTENDED_SYS_STATE', 'WIND_COV', 'SYSTEM_TIME', 'TIMESYNC']
    .every((n) => seen[n] > 0), `messages seen: ${JSON.stringify(seen)}`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

// ---- the end of the flight, and its log ----
child.kill('SIGINT')
const { code, signal } = await exited
console.log(out.trim())
check(code === 0 || code === 130 || signal === 'SIGINT', `tern fly ended (code ${code}, signal ${signal})`)
const runs = fs.existsSync(logDir) ? fs.readdirSync(logDir) : []
const params = runs.length ? path.join(logDir, runs[0], 'params.csv') : ''
const changes = params && fs.existsSync(params) ? fs.readFileSync(params, 'utf8') : ''
check(/slc\.course_kp.*2\.5.*mavlink/.test(changes), `params.csv records slc.course_kp 2.5 from mavlink`)
sock.close()
if (failures.length) {
  console.log(`${failures.length} failure(s)`)
  status = 1
}
process.exit(status)
