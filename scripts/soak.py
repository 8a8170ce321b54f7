#!/usr/bin/python3
"""Drives a running binaural_renderer for a soak: swaps rooms and turns the head while it
streams, samples its status and its resident memory, and reports.

    soak.py --pid PID [--ns /soak] [--minutes 60] [--swap-s 20] [--walk | --walk-rsao] [--out REPORT.md]

Every --swap-s seconds the next measured B-format RIR of data/rirs/bformat goes to
<ns>/binaural_renderer/impulse_response (FuMa, 2-6 s long); the head turns continuously,
one revolution every 12 s, at 50 orientations per second on .../head_orientation. Every
10 s the renderer's resident memory (/proc/PID/status VmRSS) and its last
.../status are recorded. At the end: chunks published, late and dropped, rooms accepted
and refused, the CPU share (median and worst of the status periods), and the memory's
least-squares slope over the run after its first five minutes (warm-up: the convolver
and the HRTF caches fill), in MiB per hour.

With --walk the listener walks instead: a simulated room (a 6 x 4 x 2.8 m room with a
carpeted floor and a tiled ceiling, fast mode, through the room_simulator) on
.../room_scene, then a listener walking at 1 m/s on average around an ellipse 0.9 m inside
its walls, facing where it goes, around the source in the room's middle, at 50 poses per second on .../listener_pose. The report adds the
positions refused and the late parts simulated again on the way (room changes).

With --walk-rsao the listener walks the same way (0.9 m inside the walls, at 1.6 m, past
the source at 0.7 m) in the RSAO room the renderer was started with (scripts/soak
--walk-rsao: the sample room, 6.4 x 4.8 x 2.9 m, its room model from a file). The report
adds the largest sample step of the binaural stream over the walk, beside the dry
signal's own largest step times the stream's peak over the dry signal's peak.

Exit status: 0 when the run completed with no chunk dropped, no room refused and the
renderer alive; 1 otherwise; 2 for bad arguments.
"""
import argparse
import array
import math
import os
import statistics
import sys
import time
import wave

import rospy
from geometry_msgs.msg import PoseStamped, QuaternionStamped
from room_reverb.msg import AudioBuffer, ImpulseResponse, RoomScene, StreamStatus

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RIRS = ["dixon_studio_theatre_r1", "terrys_typing_room", "st_andrews_church", "tyndall_bruce_monument"]
WARM_UP_S = 300.0


def read_wav_float(path):
    """Interleaved float samples of a 16- or 24-bit PCM WAV, its channel count and rate."""
    with wave.open(path, "rb") as w:
        channels, width, rate = w.getnchannels(), w.getsampwidth(), w.getframerate()
        raw = w.readframes(w.getnframes())
    if width == 2:
        ints, scale = array.array("h", raw), 32768.0
    elif width == 3:
        # 24-bit little-endian into the top three bytes of int32: value * 256.
        wide = bytearray(len(raw) // 3 * 4)
        wide[1::4], wide[2::4], wide[3::4] = raw[0::3], raw[1::3], raw[2::3]
        ints, scale = array.array("i", bytes(wide)), 2147483648.0
    else:
        raise ValueError(f"{path}: {8 * width}-bit samples (16 or 24 expected)")
    return [v / scale for v in ints], channels, rate


def rss_mib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError("no VmRSS")


WALK_ROOM = (6.0, 4.0, 2.8)
WALK_SOURCE = (3.0, 2.0, 1.2)  # the room's middle: the listener circles it at 1.1-2.1 m
WALK_SPEED_M_S = 1.0
RSAO_ROOM = (6.4, 4.8, 2.9)  # data/sample_room: the listener passes its source at 0.7 m
DRY = os.path.join(REPO, "data", "dry", "speech.wav")  # what scripts/soak plays


def walk_scene():
    """The walk's room: a RoomScene the room_simulator simulates in fast mode."""
    scene = RoomScene()
    scene.room.header.frame_id = "room"
    scene.room.size.x, scene.room.size.y, scene.room.size.z = WALK_ROOM
    scene.room.has_ceiling = True
    scene.room.floor_material = "carpet_thick"
    scene.room.ceiling_material = "acoustic_ceiling_tiles"
    for wall in ("wall_x_min", "wall_x_max", "wall_y_min", "wall_y_max"):
        setattr(scene.room, wall + "_material", "plaster_smooth")
    scene.source.x, scene.source.y, scene.source.z = WALK_SOURCE
    x, y = walk_position(0.0)[:2]
    scene.listener.x, scene.listener.y, scene.listener.z = x, y, 1.6
    scene.mode = "fast"
    return scene


def walk_position(t_s, room=WALK_ROOM):
    """Position and heading at t_s on an ellipse 0.9 m inside the walls, 1 m/s on average
    (0.7-1.4 m/s: uniform in the ellipse's angle, not its length)."""
    a, b = room[0] / 2 - 0.9, room[1] / 2 - 0.9
    perimeter = math.pi * (3 * (a + b) - math.sqrt((3 * a + b) * (a + 3 * b)))  # Ramanujan
    phase = 2.0 * math.pi * WALK_SPEED_M_S * t_s / perimeter
    x, y = room[0] / 2 + a * math.cos(phase), room[1] / 2 + b * math.sin(phase)
    heading = math.atan2(b * math.cos(phase), -a * math.sin(phase))
    return x, y, 1.6, heading


def slope_per_hour(samples):
    """Least-squares slope of (t_s, value) pairs, per hour."""
    if len(samples) < 3:
        return float("nan")
    mt = statistics.fmean(t for t, _ in samples)
    mv = statistics.fmean(v for _, v in samples)
    num = sum((t - mt) * (v - mv) for t, v in samples)
    den = sum((t - mt) ** 2 for t, _ in samples)
    return 3600.0 * num / den if den > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pid", type=int, required=True, help="the renderer's process id")
    parser.add_argument("--ns", default="/soak", help="the renderer's namespace")
    parser.add_argument("--minutes", type=float, default=60.0)
    parser.add_argument("--swap-s", type=float, default=20.0)
    parser.add_argument("--walk", action="store_true", help="a listener walking in a simulated room")
    parser.add_argument("--walk-rsao", action="store_true", help="a listener walking in the RSAO room given")
    parser.add_argument("--out", default="", help="write the report (Markdown) here too")
    args = parser.parse_args()
    if args.minutes <= 0 or args.swap_s <= 0:
        print("soak.py: --minutes and --swap-s must be positive", file=sys.stderr)
        return 2
    if args.walk and args.walk_rsao:
        print("soak.py: --walk and --walk-rsao exclude each other", file=sys.stderr)
        return 2
    walking = args.walk or args.walk_rsao
    walk_room = RSAO_ROOM if args.walk_rsao else WALK_ROOM
    if not os.path.exists(f"/proc/{args.pid}"):
        print(f"soak.py: no process {args.pid}", file=sys.stderr)
        return 2

    rospy.init_node("soak_driver", anonymous=True)
    base = args.ns.rstrip("/") + "/binaural_renderer/"
    rir_pub = rospy.Publisher(base + "impulse_response", ImpulseResponse, queue_size=1, latch=True)
    head_pub = rospy.Publisher(base + "head_orientation", QuaternionStamped, queue_size=10)
    scene_pub = rospy.Publisher(base + "room_scene", RoomScene, queue_size=1, latch=True)
    pose_pub = rospy.Publisher(base + "listener_pose", PoseStamped, queue_size=10)
    status = {"last": None, "cpu": [], "worst_chunk": 0.0, "pose_to_ear": []}

    def on_status(message):
        status["last"] = message
        status["cpu"].append(message.process_cpu_share)
        if message.pose_to_ear_s > 0.0:
            status["pose_to_ear"].append(message.pose_to_ear_s)
        status["worst_chunk"] = max(status["worst_chunk"], message.worst_chunk_render_s)

    rospy.Subscriber(base + "status", StreamStatus, on_status)
    # The stream's largest step between consecutive samples of one ear while it is walked
    # (the first chunks, before the walk, are left out) and its peak.
    stream = {"walking": False, "step": 0.0, "peak": 0.0, "last": [None, None]}

    def on_binaural(message):
        if not stream["walking"] or message.channel_count != 2:
            return
        samples = message.samples
        for ear in (0, 1):
            x = samples[ear::2]
            previous = stream["last"][ear]
            if previous is not None and x:
                stream["step"] = max(stream["step"], abs(x[0] - previous))
            stream["step"] = max(stream["step"], max((abs(b - a) for a, b in zip(x, x[1:])), default=0.0))
            stream["peak"] = max(stream["peak"], max((abs(v) for v in x), default=0.0))
            stream["last"][ear] = x[-1] if x else previous

    if args.walk_rsao:
        rospy.Subscriber(base + "binaural", AudioBuffer, on_binaural, queue_size=200)

    rooms = []
    for name in RIRS:
        samples, channels, rate = read_wav_float(os.path.join(REPO, "data", "rirs", "bformat", name + ".wav"))
        message = ImpulseResponse()
        message.audio.sample_rate_hz = rate
        message.audio.channel_count = channels
        message.audio.channel_layout = "fuma"
        message.audio.samples = samples
        rooms.append((name, message))

    if walking:
        if args.walk:
            scene_pub.publish(walk_scene())
        deadline = time.monotonic() + 60.0
        while not rospy.is_shutdown() and time.monotonic() < deadline:
            if status["last"] is not None and status["last"].walkable:
                break
            time.sleep(0.1)
        if status["last"] is None or not status["last"].walkable:
            last = status["last"]
            print(f"soak.py: the {'simulated' if args.walk else 'RSAO'} room did not become walkable in 60 s" +
                  (f" ({last.last_message})" if last is not None else ""))
            return 1
        stream["walking"] = True
    start = time.monotonic()
    end = start + 60.0 * args.minutes
    next_swap, next_sample, swaps = start, start, 0
    memory, load = [], []
    rate = rospy.Rate(50)
    while not rospy.is_shutdown() and time.monotonic() < end:
        now = time.monotonic()
        if not os.path.exists(f"/proc/{args.pid}"):
            print(f"soak.py: the renderer (pid {args.pid}) died after {now - start:.0f} s")
            return 1
        if not walking and now >= next_swap:
            name, message = rooms[swaps % len(rooms)]
            message.audio.header.stamp = rospy.Time.now()
            rir_pub.publish(message)
            swaps += 1
            next_swap += args.swap_s
        if now >= next_sample:
            memory.append((now - start, rss_mib(args.pid)))
            load.append(os.getloadavg()[0])
            next_sample += 10.0
        if walking:
            x, y, z, heading = walk_position(now - start, walk_room)
            pose = PoseStamped()
            pose.header.stamp = rospy.Time.now()
            pose.header.frame_id = "room"
            pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = x, y, z
            pose.pose.orientation.z, pose.pose.orientation.w = math.sin(heading / 2.0), math.cos(heading / 2.0)
            pose_pub.publish(pose)
        else:
            yaw = 2.0 * math.pi * ((now - start) / 12.0 % 1.0)
            q = QuaternionStamped()
            q.header.stamp = rospy.Time.now()
            q.header.frame_id = "head"
            q.quaternion.z, q.quaternion.w = math.sin(yaw / 2.0), math.cos(yaw / 2.0)
            head_pub.publish(q)
        rate.sleep()

    last = status["last"]
    if last is None:
        print("soak.py: no status from the renderer")
        return 1
    after_warm_up = [(t, v) for t, v in memory if t >= WARM_UP_S] or memory
    cpu = sorted(status["cpu"])
    kind = "a simulated" if args.walk else "an RSAO"
    what = (f"a listener walking at {WALK_SPEED_M_S:g} m/s in {kind} {walk_room[0]:g} x {walk_room[1]:g} x "
            f"{walk_room[2]:g} m room, 50 poses per second" if walking else
            f"a room swap every {args.swap_s:g} s ({swaps} swaps over {len(rooms)} RIRs), head turning at 50 Hz")
    step_lines = []
    if args.walk_rsao:
        dry, channels, _ = read_wav_float(DRY)
        dry = dry[::channels]
        dry_step = max(abs(b - a) for a, b in zip(dry, dry[1:]))
        dry_peak = max(abs(v) for v in dry)
        scaled = dry_step * stream["peak"] / dry_peak if dry_peak > 0 else float("nan")
        step_lines = [f"| largest sample step while walking / the dry signal's own / the dry's scaled to the stream's peak | "
                      f"{stream['step']:.4f} / {dry_step:.4f} / {scaled:.4f} (peaks {stream['peak']:.4f}, dry {dry_peak:.4f}) |"]
    lines = [
        f"| run | {args.minutes:g} min, {what} |",
        "| --- | --- |",
        f"| chunks published / late / dropped | {last.chunks_published} / {last.chunks_late} / {last.chunks_dropped} |",
        f"| rooms accepted / refused | {last.room_changes} / {last.rooms_rejected} |",
        f"| orientations refused | {last.orientations_rejected} |",
        *([f"| walkable at the end / positions outside the room | {last.walkable} / {last.listener_positions_clamped} |"]
          if walking else []),
        *step_lines,
        *([f"| pose to ear, the status periods' longest: median / max | "
           f"{1000.0 * statistics.median(status['pose_to_ear']):.1f} / {1000.0 * max(status['pose_to_ear']):.1f} ms |"]
          if walking and status["pose_to_ear"] else []),
        f"| process CPU share, median / worst status period | {statistics.median(cpu):.3f} / {cpu[-1]:.3f} |",
        f"| longest chunk render | {1000.0 * status['worst_chunk']:.1f} ms |",
        f"| audio thread scheduling | {last.audio_scheduling} |",
        f"| machine load average (1 min), median / max of the samples | {statistics.median(load):.1f} / {max(load):.1f} |",
        f"| resident memory, first / last sample | {memory[0][1]:.1f} / {memory[-1][1]:.1f} MiB |",
        f"| resident memory slope after {WARM_UP_S / 60:g} min | {slope_per_hour(after_warm_up):+.2f} MiB per hour |",
    ]
    report = "\n".join(lines)
    print(report)
    if args.out:
        with open(args.out, "w") as f:
            f.write(report + "\n")
    healthy = last.chunks_dropped == 0 and last.rooms_rejected == 0
    return 0 if healthy else 1


if __name__ == "__main__":
    sys.exit(main())
