#!/usr/bin/python3
"""Test recordings for iilfm's bag readers, written with the real ROS 1 writer.

Run with Debian's /usr/bin/python3 (python3-rosbag, python3-sensor-msgs, python3-genpy):
  make_bags.py ros1 OUTDIR      clouds_{none,bz2,lz4}.bag, livox.bag and expected.json
  make_bags.py ros2 OUTDIR      ros2_bag/ (metadata.yaml + .db3, rosbag2 sqlite3 schema, CDR)
  make_bags.py pcd2bag OUT.bag TOPIC PERIOD PCD...   one PointCloud2 message per PCD file, or, with
                                a PCD holding a time field and PERIOD > 0 given as --split PERIOD,
                                one message per PERIOD seconds of it
expected.json holds, per topic, every message's valid points exactly as written (NaN, Inf and
all-zero points left out and counted), for the C++ tests to compare with what they read.
"""
import json
import math
import os
import sqlite3
import struct
import sys

F32, F64, U8, U16 = 7, 8, 2, 4
SIZES = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 4, 8: 8}
FORMATS = {1: 'b', 2: 'B', 3: 'h', 4: 'H', 5: 'i', 6: 'I', 7: 'f', 8: 'd'}


def f32(v):
    """The float32 nearest to v, as the C++ reader will hold it."""
    return struct.unpack('<f', struct.pack('<f', v))[0]


def points(n, seed):
    """n deterministic points: x y z intensity ring time, float32-exact where they are float32."""
    out = []
    for k in range(n):
        a = seed * 0.37 + k * 0.113
        out.append([f32(2.0 + math.sin(a)), f32(0.5 * math.cos(3 * a)), f32(0.1 * k - 0.3),
                    f32((k * 7 + seed) % 256), (k + seed) % 16, f32(k * 1e-4)])
    return out


class Layout:
    """A PointCloud2 field layout: (name, offset, datatype), point step, row padding, height."""

    def __init__(self, fields, point_step, row_pad=0, height=1, big_endian=False):
        self.fields, self.point_step = fields, point_step
        self.row_pad, self.height, self.big_endian = row_pad, height, big_endian

    def pack(self, pts):
        order = '>' if self.big_endian else '<'
        width = len(pts) // self.height
        row_step = width * self.point_step + self.row_pad
        data = bytearray(b'\xab' * (row_step * self.height))  # padding bytes are not zero
        for k, p in enumerate(pts):
            base = (k // width) * row_step + (k % width) * self.point_step
            for name, offset, datatype in self.fields:
                value = p['xyzirt'.index(name[0]) if name != 'ring' else 4]
                if FORMATS[datatype] in 'bBhHiI':
                    value = int(value)
                struct.pack_into(order + FORMATS[datatype], data, base + offset, value)
        return bytes(data), width, row_step


LAYOUTS = {
    # Velodyne-like with padding inside the record.
    '/points_padded': Layout([('x', 0, F32), ('y', 4, F32), ('z', 8, F32), ('intensity', 16, F32),
                              ('ring', 20, U16), ('time', 24, F32)], 32),
    # float64 coordinates, uint8 intensity, two rows with 8 bytes of row padding.
    '/points_f64': Layout([('x', 0, F64), ('y', 8, F64), ('z', 16, F64), ('intensity', 24, U8)],
                          25, row_pad=8, height=2),
    # The big-endian flag: every value stored most significant byte first.
    '/points_be': Layout([('x', 0, F32), ('y', 4, F32), ('z', 8, F32), ('intensity', 12, U16)], 14,
                         big_endian=True),
    # is_dense false: NaN, Inf and all-zero points among the valid ones.
    '/points_sparse': Layout([('x', 0, F32), ('y', 4, F32), ('z', 8, F32),
                              ('intensity', 12, F32)], 16),
}
MESSAGES_PER_TOPIC = 3
POINTS_PER_MESSAGE = 40


def message_points(topic, index):
    pts = points(POINTS_PER_MESSAGE, seed=index + 10 * sorted(LAYOUTS).index(topic))
    if topic == '/points_sparse':
        for k in range(0, len(pts), 5):
            pts[k][k % 3] = float('nan')
        pts[3][:3] = [0.0, 0.0, 0.0]
        pts[8][:3] = [0.0, 0.0, 0.0]
        pts[11][2] = float('inf')
    return pts


def expected_entry(layout, pts, stamp_ns, header_ns):
    names = [f[0] for f in layout.fields]
    kept = [p for p in pts
            if all(math.isfinite(v) for v in p[:4]) and not (p[0] == 0 and p[1] == 0 and p[2] == 0)]
    non_finite = sum(1 for p in pts if not all(math.isfinite(v) for v in p[:4]))
    zero = len(pts) - len(kept) - non_finite
    entry = {'stamp_ns': stamp_ns, 'header_stamp_ns': header_ns, 'points_in_file': len(pts),
             'non_finite': non_finite, 'zero': zero,
             'x': [f32(p[0]) for p in kept], 'y': [f32(p[1]) for p in kept],
             'z': [f32(p[2]) for p in kept],
             'intensity': [float(p[3]) for p in kept] if 'intensity' in names else [0.0] * len(kept),
             'ring': [p[4] for p in kept] if 'ring' in names else None,
             'time': [p[5] for p in kept] if 'time' in names else None}
    return entry


def stamp_ns(index):
    return 100_000_000_000 + index * 100_000_000


def header_ns(index):
    return 1_600_000_000_000_000_000 + index * 100_000_000 + 7


def ros_time(ns):
    import genpy
    return genpy.Time(ns // 1_000_000_000, ns % 1_000_000_000)


def make_cloud_msg(layout, pts, header_stamp):
    from sensor_msgs.msg import PointCloud2, PointField
    data, width, row_step = layout.pack(pts)
    msg = PointCloud2()
    msg.header.stamp = ros_time(header_stamp)
    msg.header.frame_id = 'lidar'
    msg.height, msg.width = layout.height, width
    msg.fields = [PointField(name=n, offset=o, datatype=d, count=1) for n, o, d in layout.fields]
    msg.is_bigendian = layout.big_endian
    msg.point_step, msg.row_step = layout.point_step, row_step
    msg.data = data
    msg.is_dense = False
    return msg


LIVOX_DEFINITION = """Header header
uint64 timebase
uint32 point_num
uint8 lidar_id
uint8[3] rsvd
CustomPoint[] points
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
================================================================================
MSG: {pkg}/CustomPoint
uint32 offset_time
float32 x
float32 y
float32 z
uint8 reflectivity
uint8 tag
uint8 line
"""


def livox_class(pkg):
    import genpy.dynamic
    types = genpy.dynamic.generate_dynamic(pkg + '/CustomMsg', LIVOX_DEFINITION.format(pkg=pkg))
    return types[pkg + '/CustomMsg'], types[pkg + '/CustomPoint']


def write_ros1(out):
    import rosbag
    from std_msgs.msg import String
    expected = {}
    for compression in ('none', 'bz2', 'lz4'):
        path = os.path.join(out, 'clouds_%s.bag' % compression)
        # A small chunk threshold spreads the messages over many chunks and index records.
        with rosbag.Bag(path, 'w', compression=compression, chunk_threshold=3000) as bag:
            for index in range(MESSAGES_PER_TOPIC):
                for topic in sorted(LAYOUTS):
                    layout = LAYOUTS[topic]
                    pts = message_points(topic, index)
                    bag.write(topic, make_cloud_msg(layout, pts, header_ns(index)),
                              ros_time(stamp_ns(index)))
                    if compression == 'none':
                        expected.setdefault(topic, {'type': 'sensor_msgs/PointCloud2',
                                                    'messages': []})
                        expected[topic]['messages'].append(
                            expected_entry(layout, pts, stamp_ns(index), header_ns(index)))
                bag.write('/chatter', String(data='frame %d' % index), ros_time(stamp_ns(index)))
    expected['/chatter'] = {'type': 'std_msgs/String', 'messages': [None] * MESSAGES_PER_TOPIC}

    with rosbag.Bag(os.path.join(out, 'livox.bag'), 'w', compression='lz4') as bag:
        for pkg, topic in (('livox_ros_driver', '/livox/lidar'), ('livox_ros_driver2', '/livox2')):
            Msg, Point = livox_class(pkg)
            expected[topic] = {'type': pkg + '/CustomMsg', 'messages': []}
            for index in range(MESSAGES_PER_TOPIC):
                pts = points(POINTS_PER_MESSAGE, seed=index + 50)
                pts[4][:3] = [0.0, 0.0, 0.0]
                timebase = header_ns(index)
                msg = Msg()
                msg.header.stamp = ros_time(timebase)
                msg.header.frame_id = 'livox_frame'
                msg.timebase = timebase
                msg.point_num = len(pts)
                msg.lidar_id = 1
                msg.rsvd = [0, 0, 0]
                msg.points = [Point(offset_time=k * 1000, x=p[0], y=p[1], z=p[2],
                                    reflectivity=int(p[3]), tag=0x10, line=p[4])
                              for k, p in enumerate(pts)]
                bag.write(topic, msg, ros_time(stamp_ns(index)))
                entry = expected_entry(Layout([('x', 0, F32), ('intensity', 0, U8), ('ring', 0, U16),
                                               ('time', 0, F64)], 0), pts, stamp_ns(index),
                                       timebase)
                kept = [k for k, p in enumerate(pts) if not (p[0] == 0 and p[1] == 0 and p[2] == 0)]
                entry['time'] = [(timebase + k * 1000) * 1e-9 for k in kept]
                expected[topic]['messages'].append(entry)
    with open(os.path.join(out, 'expected.json'), 'w') as f:
        json.dump(expected, f)


class Cdr:
    """CDR little- or big-endian writer: values aligned to their size from the start of the body."""

    def __init__(self, big_endian=False):
        self.order = '>' if big_endian else '<'
        self.body = bytearray()
        self.header = b'\x00\x00\x00\x00' if big_endian else b'\x00\x01\x00\x00'

    def put(self, fmt, value):
        size = struct.calcsize(fmt)
        self.body += b'\x00' * ((-len(self.body)) % size)
        self.body += struct.pack(self.order + fmt, value)

    def string(self, text):
        raw = text.encode() + b'\x00'
        self.put('I', len(raw))
        self.body += raw

    def bytes(self):
        return self.header + bytes(self.body)


def cdr_pointcloud2(layout, pts, header_stamp, big_endian_cdr):
    data, width, row_step = layout.pack(pts)
    c = Cdr(big_endian_cdr)
    c.put('i', header_stamp // 1_000_000_000)
    c.put('I', header_stamp % 1_000_000_000)
    c.string('lidar')
    c.put('I', layout.height)
    c.put('I', width)
    c.put('I', len(layout.fields))
    for name, offset, datatype in layout.fields:
        c.string(name)
        c.put('I', offset)
        c.put('B', datatype)
        c.put('I', 1)
    c.put('B', 1 if layout.big_endian else 0)
    c.put('I', layout.point_step)
    c.put('I', row_step)
    c.put('I', len(data))
    c.body += data
    c.put('B', 0)
    return c.bytes()


def write_ros2(out):
    folder = os.path.join(out, 'ros2_bag')
    os.makedirs(folder, exist_ok=True)
    db_path = os.path.join(folder, 'ros2_bag_0.db3')
    if os.path.exists(db_path):
        os.remove(db_path)
    db = sqlite3.connect(db_path)
    db.executescript("""
      CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
      INSERT INTO schema VALUES (3, 'humble');
      CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                          serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
      CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
                            timestamp INTEGER NOT NULL, data BLOB NOT NULL);
      CREATE INDEX timestamp_idx ON messages (timestamp ASC);""")
    topics = [(1, '/points_padded', 'sensor_msgs/msg/PointCloud2', False),
              (2, '/points_cdr_be', 'sensor_msgs/msg/PointCloud2', True),
              (3, '/chatter', 'std_msgs/msg/String', False)]
    expected = {}
    for topic_id, name, type_name, big in topics:
        db.execute('INSERT INTO topics VALUES (?, ?, ?, ?, ?)', (topic_id, name, type_name, 'cdr', ''))
        expected[name] = {'type': type_name, 'messages': []}
    count = 0
    # Inserted newest first: the reader must order by timestamp, not by row id.
    for index in reversed(range(MESSAGES_PER_TOPIC)):
        for topic_id, name, type_name, big in topics:
            if name == '/chatter':
                c = Cdr()
                c.string('frame %d' % index)
                blob = c.bytes()
                expected[name]['messages'].insert(0, None)
            else:
                layout = LAYOUTS['/points_padded']
                pts = message_points('/points_padded', index)
                blob = cdr_pointcloud2(layout, pts, header_ns(index), big)
                expected[name]['messages'].insert(
                    0, expected_entry(layout, pts, stamp_ns(index), header_ns(index)))
            db.execute('INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)',
                       (topic_id, stamp_ns(index), blob))
            count += 1
    db.commit()
    db.close()
    with open(os.path.join(folder, 'metadata.yaml'), 'w') as f:
        f.write("""rosbag2_bagfile_information:
  version: 5
  storage_identifier: sqlite3
  relative_file_paths:
    - ros2_bag_0.db3
  message_count: %d
""" % count)
    with open(os.path.join(out, 'expected_ros2.json'), 'w') as f:
        json.dump(expected, f)


def read_pcd(path):
    """Our PCD writer's binary output: header lines, then packed little-endian records."""
    with open(path, 'rb') as f:
        raw = f.read()
    header, offset = {}, 0
    while True:
        end = raw.index(b'\n', offset)
        line = raw[offset:end].decode().split()
        offset = end + 1
        if line and not line[0].startswith('#'):
            header[line[0]] = line[1:]
        if line and line[0] == 'DATA':
            break
    assert header['DATA'] == ['binary'], path
    fields, layout, at = header['FIELDS'], [], 0
    for name, size, kind in zip(fields, header['SIZE'], header['TYPE']):
        size = int(size)
        datatype = {('F', 4): F32, ('F', 8): F64, ('U', 1): U8, ('U', 2): U16}[(kind, size)]
        layout.append((name, at, datatype))
        at += size
    n = int(header['POINTS'][0])
    return layout, at, raw[offset:offset + n * at], n


def pcd_cloud_msg(layout, step, data, n, stamp):
    from sensor_msgs.msg import PointCloud2, PointField
    msg = PointCloud2()
    msg.header.stamp = ros_time(stamp)
    msg.header.frame_id = 'lidar'
    msg.height, msg.width = 1, n
    msg.fields = [PointField(name=name, offset=o, datatype=d, count=1) for name, o, d in layout]
    msg.is_bigendian = False
    msg.point_step, msg.row_step = step, step * n
    msg.data = data
    msg.is_dense = True
    return msg


def pcd2bag(args):
    """pcd2bag OUT.bag TOPIC [--split PERIOD] [--start NS] [--compression C] PCD..."""
    import rosbag
    out, topic, rest = args[0], args[1], args[2:]
    split, start, compression = 0.0, 1_600_000_000_000_000_000, 'lz4'
    while rest and rest[0].startswith('--'):
        if rest[0] == '--split':
            split = float(rest[1])
        elif rest[0] == '--start':
            start = int(rest[1])
        elif rest[0] == '--compression':
            compression = rest[1]
        rest = rest[2:]
    period_ns = 100_000_000
    with rosbag.Bag(out, 'w', compression=compression) as bag:
        frame = 0
        for pcd in rest:
            layout, step, data, n = read_pcd(pcd)
            if split <= 0:
                stamp = start + frame * period_ns
                bag.write(topic, pcd_cloud_msg(layout, step, data, n, stamp), ros_time(stamp))
                frame += 1
                continue
            time_at = [o for name, o, d in layout if name == 'time'][0]
            times = [struct.unpack_from('<d', data, k * step + time_at)[0] for k in range(n)]
            first = 0
            while first < n:
                slot = int(times[first] // split)
                last = first
                while last < n and int(times[last] // split) == slot:
                    last += 1
                stamp = start + int(round(slot * split * 1e9))
                bag.write(topic, pcd_cloud_msg(layout, step, data[first * step:last * step],
                                               last - first, stamp), ros_time(stamp))
                first = last


if __name__ == '__main__':
    command = sys.argv[1]
    if command == 'ros1':
        write_ros1(sys.argv[2])
    elif command == 'ros2':
        write_ros2(sys.argv[2])
    elif command == 'pcd2bag':
        pcd2bag(sys.argv[2:])
    else:
        sys.exit('unknown command ' + command)
