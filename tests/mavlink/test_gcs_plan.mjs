// QGroundControl's own fixed-wing test plan (tests/data/qgc_plans/PX4SITL-ArduPlane.plan) uploaded
// over MAVLink unchanged, as QGroundControl's Plan view sends it, against node-mavlink playing the
// ground station:
//
//   node test_gcs_plan.mjs TERN MISSION WORK_DIR
//
// It flies MISSION with `tern fly --realtime --speed 3 --gcs --plan` the same plan (so that home is
// the plan's), then uploads the plan's items as MISSION_ITEM_INTs (params as QGroundControl writes
// them, null as NaN; degrees as degE7): every item accepted (a NAV_LOITER_TO_ALT, a DO_CHANGE_SPEED
// of ground speed, a loiter whose altitude is NaN, a terrain-frame waypoint among them), read back
// equal, HOME_POSITION at the plan's planned home, and MISSION_CURRENT following the upload. Then a
// mission with DO_SET_HOME (where the aircraft is, and a location given) before its
// RETURN_TO_LAUNCH: accepted and read back equal; a DO_SET_HOME whose param1 is 2 refused with
// INVALID_PARAM1 and a STATUSTEXT naming the item. After the flight, `tern export plan RUN` writes
// the mission as flown, the last upload's: its two waypoints and the return as a loiter over the
// home its second DO_SET_HOME gave.
// Exit 0 when all hold; 1 with one line per failure.
import { spawnSync } from 'node:child_process'
import fs from 'node:fs'
import path from 'node:path'
import { common } from 'node-mavlink'
import { openGcs } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_plan.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const R = common.MavMissionResult
const Cmd = common.MavCmd
const planFile = path.join(path.dirname(new URL(import.meta.url).pathname), '..', 'data', 'qgc_plans', 'PX4SITL-ArduPlane.plan')
const plan = JSON.parse(fs.readFileSync(planFile, 'utf8'))

const gcs = await openGcs()
const { item, upload, download, differences, command } = missionClient(gcs)
const flight = flyWithGcs(tern, mission, work, gcs, 600, 3, ['--plan', planFile])
const num = (v) => (v === null ? NaN : v)
const [lat0, lon0] = plan.mission.plannedHomePosition

try {
  await gcs.next('HEARTBEAT', (d) => (d.baseMode & 128) !== 0, 20000) // armed: flying
  const homeP = gcs.next('HOME_POSITION', () => true, 3000)
  await command(Cmd.REQUEST_MESSAGE, [242])
  const home = await homeP
  const off = Math.hypot(home.latitude / 1e7 - lat0, home.longitude / 1e7 - lon0) * 111320
  check(off < 20, `HOME_POSITION ${off.toFixed(1)} m from the plan's planned home (the world's origin, the first fix's noise)`)
  const items = plan.mission.items.map((j, seq) => {
    const p = j.params.map(num)
    return item(seq, j.command, j.frame, p[4], p[5], p[6], p.slice(0, 4))
  })
  const ack = await upload(items)
  check(ack.type === R.ACCEPTED, `QGroundControl's ${items.length} items accepted (${ack.type}; ${gcs.texts.slice(-1)})`)
  const diff = differences(items, await download())
  check(diff.length === 0, `read back equal${diff.length ? ': ' + diff.join('; ') : ''}`)
  const current = await gcs.next('MISSION_CURRENT', (m) => m.seq >= 1, 60000)
  check(current.total === items.length, `MISSION_CURRENT follows the upload: item ${current.seq} of ${current.total}`)
  const [lat, lon] = [lat0 + 0.004, lon0] // 445 m north of home
  const Rel = common.MavFrame.GLOBAL_RELATIVE_ALT_INT
  const rehome = [item(0, Cmd.NAV_WAYPOINT, Rel, lat, lon, 80), item(1, Cmd.DO_SET_HOME, common.MavFrame.MISSION, 0, 0, 0, [1, 0, 0, 0]),
    item(2, Cmd.NAV_WAYPOINT, Rel, lat, lon + 0.004, 60), item(3, Cmd.DO_SET_HOME, Rel, lat0, lon0 + 0.004, 0, [0, 0, 0, NaN]),
    item(4, Cmd.NAV_RETURN_TO_LAUNCH, Rel, 0, 0, 0)]
  const rehomed = await upload(rehome)
  check(rehomed.type === R.ACCEPTED, `DO_SET_HOME (current, and a location) before RTL accepted (${rehomed.type}; ${gcs.texts.slice(-1)})`)
  const rediff = differences(rehome, await download())
  check(rediff.length === 0, `DO_SET_HOME's mission read back equal${rediff.length ? ': ' + rediff.join('; ') : ''}`)
  rehome[1].param1 = 2
  const refused = await upload(rehome)
  const said = gcs.texts.slice(-4).join('') // STATUSTEXT carries 50 characters a message
  check(refused.type === R.INVALID_PARAM1 && said.includes('mission item 1 (DO_SET_HOME)'),
    `DO_SET_HOME with param1 2 refused INVALID_PARAM1 (${refused.type}) naming the item (${said})`)
  // the upload flown a while before the flight ends (MISSION_CURRENT comes at 1 Hz; the planner lists it at its next step)
  let flying = null
  for (let k = 0; k < 2; k++) flying = await gcs.next('MISSION_CURRENT', (m) => m.total === rehome.length, 10000)
  check(flying.total === rehome.length, `the refused upload left the DO_SET_HOME mission flown (${flying.total} items)`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

await flight.finish(check)
try {
  const run = path.join(flight.logDir, fs.readdirSync(flight.logDir).sort().at(-1)) // this flight's: the newest
  const out = path.join(work, 'flown.plan')
  fs.rmSync(out, { force: true })
  const exported = spawnSync(tern, ['export', 'plan', run, out], { encoding: 'utf8' })
  check(exported.status === 0, `tern export plan RUN (${exported.status}): ${exported.stdout.trim()} ${exported.stderr.trim()}`)
  const nav = JSON.parse(fs.readFileSync(out, 'utf8')).mission.items.filter((i) => i.command < 100)
  check(nav.map((i) => i.command).join() === '16,16,17', `the plan as flown: nav items ${nav.map((i) => i.command).join()} (16,16,17)`)
  const [lat, lon] = nav[2].params.slice(4, 6) // the loiter's; the home given: (lat0, lon0 + 0.004)
  const off = Math.hypot(lat - lat0, (lon - lon0 - 0.004) * Math.cos(lat * Math.PI / 180)) * 111320
  check(off < 1, `its return loiters over the home DO_SET_HOME gave (${off.toFixed(2)} m off)`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}
process.exit(report(failures, gcs))
