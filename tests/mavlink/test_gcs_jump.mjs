// A GCS's DO_JUMP flown its repeat count (core/apps/mavlink/mission_items.hpp: the upload unrolled
// into the waypoints it flies) against node-mavlink playing the ground station:
//
//   node test_gcs_jump.mjs TERN MISSION WORK_DIR
//
// It flies MISSION with `tern fly --realtime --speed 6 --gcs`, uploads
//   0 NAV_WAYPOINT A, 1 NAV_WAYPOINT B, 2 DO_JUMP to 0 repeat 2, 3 NAV_WAYPOINT C, 4 NAV_LOITER_UNLIM
// and follows MISSION_CURRENT (1 Hz of wall time, legs of 300 m: several samples each): the items
// flown are 0 1 0 1 0 1 3 4 (the jump taken twice, as PX4 and ArduPilot count it), and the
// download still lists the five items as uploaded.
// Exit 0 when all hold; 1 with one line per failure.
import { common } from 'node-mavlink'
import { openGcs } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_jump.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const R = common.MavMissionResult
const Cmd = common.MavCmd
const Frame = common.MavFrame
const M = 111320 // m per degree of latitude (flat earth: enough within a km)

const gcs = await openGcs()
const { item, upload, download, differences, command } = missionClient(gcs)
const flight = flyWithGcs(tern, mission, work, gcs, 400, 6)

try {
  await gcs.next('HEARTBEAT', (d) => (d.baseMode & 128) !== 0, 20000) // armed: flying
  const homeP = gcs.next('HOME_POSITION', () => true, 3000)
  await command(Cmd.REQUEST_MESSAGE, [242])
  const home = await homeP
  const h = { lat: home.latitude / 1e7, lon: home.longitude / 1e7 }
  const at = (north, east) => [h.lat + north / M, h.lon + east / (M * Math.cos((h.lat * Math.PI) / 180))]
  const plan = [
    item(0, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(300, 0), 100, [0, 0, 0, NaN]),
    item(1, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(300, 300), 100, [0, 0, 0, NaN]),
    item(2, Cmd.DO_JUMP, Frame.MISSION, 0, 0, 0, [0, 2, 0, 0]),
    item(3, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(-300, 300), 100, [0, 0, 0, NaN]),
    item(4, Cmd.NAV_LOITER_UNLIM, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(0, 0), 100, [0, 0, 80, NaN]),
  ]
  const flown = []
  const stop = gcs.listen('MISSION_CURRENT', (m) => { if (flown[flown.length - 1] !== m.seq) flown.push(m.seq) })
  check((await upload(plan)).type === R.ACCEPTED, 'a plan with DO_JUMP to item 0, repeat 2, accepted')
  await gcs.next('MISSION_CURRENT', (m) => m.seq === 4, 120000)
  stop()
  // the first samples may still show the configured mission's item before the upload took over
  const since = flown.indexOf(0)
  const sequence = flown.slice(since).join(' ')
  check(sequence === '0 1 0 1 0 1 3 4', `the items flown: ${sequence} (0 1 0 1 0 1 3 4: the jump taken twice)`)
  check(differences(plan, await download()).length === 0, 'the download lists the plan as uploaded')
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

await flight.finish(check)
process.exit(report(failures, gcs))
