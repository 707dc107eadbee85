"""Read odoloc's LCM event logs with the Python standard library only.

Debian 12 has no python3-lcm, so this reads LCM's event-log format itself
(the file `odoloc sim --out DIR` writes as DIR/odoloc.lcmlog, or lcm-logger's)
and decodes odoloc's messages with the types lcm-gen -p generated at build
time (package odoloc_lcm, installed beside this module). docs/lcm.md,
"Python".

    import odoloc_lcmlog
    fused = odoloc_lcmlog.load("run/odoloc.lcmlog", "ODOLOC_POSE_FUSED")
    xs = [m["x"] for m in fused]            # one dict per event, in log order

    python3 -m odoloc_lcmlog run/odoloc.lcmlog --channel ODOLOC_ODOMETRY --csv

The event-log format (LCM's lcm_eventlog.c): events one after another, each
a big-endian header of sync word 0xEDA1DA01 (uint32), event number (int64),
timestamp (int64, microseconds), channel length (int32), data length
(int32), then the channel name and the message bytes. A message starts with
its type's 64-bit fingerprint.

Bad input loses nothing that is whole: bytes that are no event are skipped
up to the next sync word and counted (LogReader.skipped_bytes), a truncated
last event is counted (LogReader.truncated), a message that does not decode
as the type its fingerprint names is returned undecoded (Event.message None)
and counted, and text from the log is escaped before it reaches a terminal.
"""

import argparse
import csv
import io
import json
import math
import re
import signal
import struct
import sys

import odoloc_lcm

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">IqqII")
# A channel name is at most 63 bytes (LCM_MAX_CHANNEL_NAME_LENGTH); a message
# at most what LCM's UDP transport fragments (well under 256 MiB).
_MAX_CHANNEL = 63
_MAX_DATA = 1 << 28

TYPES = {
    cls._get_packed_fingerprint(): cls
    for cls in (
        getattr(odoloc_lcm, name)
        for name in dir(odoloc_lcm)
        if hasattr(getattr(odoloc_lcm, name), "_get_packed_fingerprint")
    )
}


class Event:
    """One logged event: number, timestamp (us), channel, bytes, and the
    decoded message (an odoloc_lcm type) or None."""

    __slots__ = ("number", "timestamp", "channel", "data", "message")

    def __init__(self, number, timestamp, channel, data, message):
        self.number = number
        self.timestamp = timestamp
        self.channel = channel
        self.data = data
        self.message = message


def decode(data):
    """The odoloc_lcm message in `data` (bytes), or None when its fingerprint
    is none of odoloc's types or the bytes are not that type's message (too
    short, too long, a string that is not UTF-8 ...)."""
    cls = TYPES.get(bytes(data[:8]))
    if cls is None:
        return None
    buf = io.BytesIO(data)
    buf.seek(8)
    try:
        message = cls._decode_one(buf)
    except (struct.error, ValueError, UnicodeDecodeError, IndexError):
        return None
    return message if buf.tell() == len(data) else None


class LogReader:
    """Iterates over the events of an LCM event log (a path or a binary file
    object). Counts what it could not read: skipped_bytes (no event there),
    truncated (a last event cut short), malformed (events whose message did
    not decode)."""

    def __init__(self, source):
        self._file = source if hasattr(source, "read") else open(source, "rb")
        self.skipped_bytes = 0
        self.truncated = False
        self.malformed = 0

    def close(self):
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __iter__(self):
        data = self._file.read()
        at = 0
        sync = struct.pack(">I", SYNC)
        while at < len(data):
            if data[at:at + 4] != sync:
                found = data.find(sync, at + 1)
                end = len(data) if found < 0 else found
                self.skipped_bytes += end - at
                at = end
                continue
            if at + _HEADER.size > len(data):
                self.truncated = True
                return
            _, number, timestamp, channel_len, data_len = _HEADER.unpack_from(data, at)
            body = at + _HEADER.size
            if channel_len > _MAX_CHANNEL or data_len > _MAX_DATA:
                self.skipped_bytes += 4  # a sync word in the data: not an event
                at += 4
                continue
            if body + channel_len + data_len > len(data):
                self.truncated = True
                return
            channel = data[body:body + channel_len].decode("utf-8", "replace")
            payload = data[body + channel_len:body + channel_len + data_len]
            message = decode(payload)
            if message is None:
                self.malformed += 1
            yield Event(number, timestamp, channel, payload, message)
            at = body + channel_len + data_len


def to_dict(message):
    """A message as a dict of its fields, in the .lcm file's order: nested
    types as dicts, arrays as lists (lcm-gen's decoders give tuples, and
    for boolean arrays a map, which this consumes)."""
    out = {}
    for name in message.__slots__:
        value = getattr(message, name)
        if isinstance(value, (list, tuple, map)):
            value = [to_dict(v) if hasattr(v, "__slots__") else v for v in value]
        elif hasattr(value, "__slots__"):
            value = to_dict(value)
        out[name] = value
    return out


def rows(log, channel=None):
    """The decoded events of `log` (a LogReader) as dicts (to_dict) with the
    event's "channel" and "timestamp" (us) first, in log order; only channels
    fully matching the compiled regular expression `channel` when given."""
    for event in log:
        if event.message is None or (channel and not channel.fullmatch(event.channel)):
            continue
        row = {"channel": event.channel, "timestamp": event.timestamp}
        row.update(to_dict(event.message))
        yield row


def load(path, channel=None):
    """Every decoded message of the log at `path` (rows), as a list; only
    channels fully matching the regular expression `channel` when given.
    Events that do not decode are left out."""
    with LogReader(path) as log:
        return list(rows(log, re.compile(channel) if channel is not None else None))


_UNPRINTABLE = re.compile(r"[\x00-\x1f\x7f-\x9f]")


def printable(text):
    """`text` with control characters as \\xNN: data for a terminal, never
    escape sequences."""
    return _UNPRINTABLE.sub(lambda m: "\\x%02x" % ord(m.group()), text)


def _flat(row, prefix=""):
    """A row for CSV: fixed arrays as name[i], nested lists as JSON text."""
    out = {}
    for key, value in row.items():
        if isinstance(value, list) and all(not isinstance(v, (dict, list)) for v in value):
            for i, v in enumerate(value):
                out["%s%s[%d]" % (prefix, key, i)] = v
        elif isinstance(value, (list, dict)):
            out[prefix + key] = json.dumps(value, ensure_ascii=True)
        elif isinstance(value, str):
            out[prefix + key] = printable(value)
        else:
            out[prefix + key] = value
    return out


def _json_safe(value):
    """JSON has no NaN or infinity: null, as JSON encoders do."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [_json_safe(v) for v in value]
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    return value


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m odoloc_lcmlog",
        description="Print the odoloc messages of an LCM event log as JSON lines "
        "(default) or CSV (one channel).")
    parser.add_argument("log", help="the LCM event log (odoloc sim --out DIR: DIR/odoloc.lcmlog)")
    parser.add_argument("--channel", help="only channels fully matching this regular expression")
    parser.add_argument("--csv", action="store_true",
                        help="CSV with a header line; needs --channel naming one message type")
    args = parser.parse_args(argv)
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, lambda number, frame: sys.exit(128 + number))
    try:
        wanted = re.compile(args.channel) if args.channel is not None else None
    except re.error as error:
        parser.error("--channel: not a regular expression: %s" % error)
    try:
        with LogReader(args.log) as log:
            writer = None
            for row in rows(log, wanted):
                if not args.csv:
                    print(json.dumps(_json_safe(row), ensure_ascii=True, allow_nan=False))
                    continue
                flat = _flat(row)
                if writer is None:
                    writer = csv.DictWriter(sys.stdout, fieldnames=list(flat), lineterminator="\n")
                    writer.writeheader()
                elif list(flat) != writer.fieldnames:
                    sys.exit("odoloc_lcmlog: --csv: %s carries another message type than the "
                             "first row's; name one channel" % printable(row["channel"]))
                writer.writerow(flat)
            problems = []
            if log.malformed:
                problems.append("%d event%s did not decode"
                                % (log.malformed, "" if log.malformed == 1 else "s"))
            if log.skipped_bytes:
                problems.append("%d byte%s were no event"
                                % (log.skipped_bytes, "" if log.skipped_bytes == 1 else "s"))
            if log.truncated:
                problems.append("the last event is cut short")
            if problems:
                print("odoloc_lcmlog: %s: %s" % (printable(args.log), "; ".join(problems)),
                      file=sys.stderr)
    except OSError as error:
        sys.exit("odoloc_lcmlog: %s: %s" % (printable(args.log), printable(error.strerror or "")))
    except BrokenPipeError:
        sys.exit(0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
