// A fleet's vehicles on one ground-station port, each a MAVLink system of its own
// (core/apps/mavlink/gcs_link.hpp; docs/ground-station.md, "Several vehicles") against
// node-mavlink playing the ground station:
//
//   node test_gcs_fleet.mjs TERN FLEET_MISSION WORK_DIR
//
// It flies FLEET_MISSION (configs/missions/formation.yaml: uav1, uav2, uav3 -> system ids 1, 2, 3)
// with `tern fly --realtime --speed 5 --gcs` and checks, on the one port:
//   - HEARTBEATs from system ids 1, 2 and 3;
//   - GLOBAL_POSITION_INT from each, at positions more than 50 m apart (they fly 150 m apart);
//   - PARAM_SET slc.course_kp addressed to system 2: answered by system 2 alone; read back from
//     each (PARAM_REQUEST_READ, after the set was applied): 2 holds the new value, 1 and 3 the old;
//   - a rally point (the mission protocol, mission_type RALLY) uploaded to system 2: acknowledged by
//     2 alone; downloaded from each: 2 has it, 1 and 3 none;
//   - MAV_CMD_REQUEST_MESSAGE AUTOPILOT_VERSION to system 3: acknowledged by 3 alone, whose
//     AUTOPILOT_VERSION has uid 3; to system 0 (every system): acknowledged by all three;
//   - the same command to system 9, which no vehicle has: no answer, and the end-of-run line counts
//     exactly one frame "for no vehicle here".
// Exit 0 when all hold; 1 with one line per failure.
import { common } from 'node-mavlink'
import { openGcs } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_fleet.mjs TERN FLEET_MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const SYSTEMS = [1, 2, 3]
const AUTOPILOT_VERSION = 148
const M = 111320 // m per degree of latitude (flat earth: enough within a km)

const gcs = await openGcs()
const flight = flyWithGcs(tern, mission, work, gcs, 300, 5)
const to = (system, m) => Object.assign(m, { targetSystem: system, targetComponent: 1 })
const sorted = (xs) => [...xs].sort((a, b) => a - b).join(',')

/** The systems that sent `name` (matching `match`) within `ms` of wall time. */
async function senders(name, ms, match = () => true) {
  const from = new Set()
  const stop = gcs.listen(name, (d, h) => { if (match(d)) from.add(h.sysid) })
  await new Promise((resolve) => setTimeout(resolve, ms))
  stop()
  return from
}

/** slc.course_kp as system `system` reports it (PARAM_REQUEST_READ by id). */
async function courseKp(system) {
  const answer = gcs.next('PARAM_VALUE', (d, h) => h.sysid === system && d.paramId === 'slc.course_kp', 3000)
  gcs.send(Object.assign(to(system, new common.ParamRequestRead()), { paramId: 'slc.course_kp', paramIndex: -1 }))
  return (await answer).paramValue
}

/** MAV_CMD_REQUEST_MESSAGE AUTOPILOT_VERSION to `system`: the systems that acknowledged it within 1.5 s. */
async function requestVersion(system) {
  const acks = senders('COMMAND_ACK', 1500, (d) => d.command === common.MavCmd.REQUEST_MESSAGE)
  const c = to(system, new common.CommandLong())
  c.command = common.MavCmd.REQUEST_MESSAGE
  c._param1 = AUTOPILOT_VERSION
  gcs.send(c)
  return acks
}

try {
  await gcs.next('HEARTBEAT', () => true, 20000) // the flight has started
  const beating = await senders('HEARTBEAT', 2500) // 1 Hz each
  check(sorted(beating) === '1,2,3', `HEARTBEATs on the one port from systems ${sorted(beating)} (1,2,3)`)

  const where = {}
  const stop = gcs.listen('GLOBAL_POSITION_INT', (d, h) => { where[h.sysid] = { lat: d.lat / 1e7, lon: d.lon / 1e7 } })
  await Promise.all(SYSTEMS.map((s) => gcs.next('GLOBAL_POSITION_INT', (d, h) => h.sysid === s, 10000)))
  stop()
  const apart = (a, b) => Math.hypot((a.lat - b.lat) * M, (a.lon - b.lon) * M * Math.cos((a.lat * Math.PI) / 180))
  const gaps = [[1, 2], [2, 3], [1, 3]].map(([a, b]) => apart(where[a], where[b]))
  check(gaps.every((g) => g > 50), `GLOBAL_POSITION_INT from each system, apart by ${gaps.map((g) => g.toFixed(0)).join(', ')} m (1-2, 2-3, 1-3; > 50)`)

  const before = await courseKp(1)
  const value = Math.fround(before + 1.25)
  const answered = senders('PARAM_VALUE', 1500, (d) => d.paramId === 'slc.course_kp')
  gcs.send(Object.assign(to(2, new common.ParamSet()), { paramId: 'slc.course_kp', paramValue: value, paramType: common.MavParamType.REAL32 }))
  check(sorted(await answered) === '2', `PARAM_SET slc.course_kp ${value} to system 2 answered by systems ${sorted(await answered)} (2)`)
  await new Promise((resolve) => setTimeout(resolve, 1000)) // past the echo of a set not yet applied: the values held
  const back = []
  for (const s of SYSTEMS) back.push(await courseKp(s))
  check(back[1] === value && back[0] === before && back[2] === before,
    `slc.course_kp read back from systems 1, 2, 3: ${back.join(', ')} (${before}, ${value}, ${before})`)

  const RALLY = 2
  const rally = missionClient(gcs, 2)
  const point = rally.item(0, common.MavCmd.NAV_RALLY_POINT, common.MavFrame.GLOBAL_RELATIVE_ALT_INT, where[2].lat, where[2].lon, 90, [0, 0, 0, 0], RALLY)
  const acked = senders('MISSION_ACK', 1500)
  check((await rally.upload([point], RALLY)).type === common.MavMissionResult.ACCEPTED, 'a rally point uploaded to system 2 accepted')
  check(sorted(await acked) === '2', `its MISSION_ACK from systems ${sorted(await acked)} (2)`)
  const points = []
  for (const s of SYSTEMS) points.push((await missionClient(gcs, s).download(RALLY)).length)
  check(points.join(',') === '0,1,0', `rally points downloaded from systems 1, 2, 3: ${points.join(', ')} (0, 1, 0)`)

  const versions = senders('AUTOPILOT_VERSION', 1500)
  const uid = gcs.next('AUTOPILOT_VERSION', (d, h) => h.sysid === 3, 1500)
  const to3 = await requestVersion(3)
  check(sorted(to3) === '3' && BigInt((await uid).uid) === 3n, `a command to system 3 acknowledged by systems ${sorted(to3)} (3), AUTOPILOT_VERSION from ${sorted(await versions)}`)
  const toAll = await requestVersion(0)
  check(sorted(toAll) === '1,2,3', `a command to system 0 (every system) acknowledged by systems ${sorted(toAll)} (1,2,3)`)
  const toNobody = await requestVersion(9)
  check(toNobody.size === 0, `a command to system 9 (no vehicle) acknowledged by ${toNobody.size} systems (0)`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

const out = await flight.finish(check)
const ignored = out.match(/; (\d+) for no vehicle here/)
check(ignored && ignored[1] === '1', `end of run: ${ignored ? ignored[1] : 'no count of'} frames for no vehicle here (1: the command to system 9)`)
process.exit(report(failures, gcs))
