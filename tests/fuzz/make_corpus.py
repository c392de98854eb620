#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/).

Reproducible: the same files every run (names are the seeds' descriptions).
Run it from anywhere: python3 tests/fuzz/make_corpus.py. Each target's input
format is described at the top of its fuzz_<target>.cpp.

Seeds: valid requests on real variables (FC3, FC16, FC23 of #9000, #100, #1,
the work offsets, the unlock then a configuration write, a macro run), the
refusals of the specification's order of checks, and frames in the spirit of
the public libmodbus CVEs:
  CVE-2019-14462 / CVE-2019-14463: FC16 / FC23 whose byte count and quantity
    disagree with each other or with the length of the frame (libmodbus read
    past its buffer);
  CVE-2022-0367: FC23 whose write address plus quantity runs past the map
    (libmodbus wrote past its mapping).
RTU (rtu_framer): valid frames to address 1, broadcast writes and reads, other
addresses, bad CRCs, frames of 1-3 and 257+ bytes, frames split by a gap just
below and at the silence, back-to-back frames, polls around the silence, other
bauds and addresses.
"""
import json
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
CORPUS = os.path.join(HERE, "corpus")
REGISTER_MAP = json.load(open(os.path.join(ROOT, "macros", "register_map.json")))
UNLOCK_CODE = REGISTER_MAP["unlock_code"]


def reg(number):
    """Holding register of variable #number (register_codec.hpp contract 1)."""
    return 4 * number


def words(*values):
    """The registers of doubles, big-endian words, most significant first."""
    return b"".join(struct.pack(">d", v) for v in values)


def fc3(address, quantity):
    return struct.pack(">BHH", 0x03, address, quantity)


def fc16(address, data, quantity=None, byte_count=None):
    quantity = len(data) // 2 if quantity is None else quantity
    byte_count = len(data) if byte_count is None else byte_count
    return struct.pack(">BHHB", 0x10, address, quantity, byte_count & 0xFF) + data


def fc23(read_address, read_quantity, write_address, data, write_quantity=None, byte_count=None):
    write_quantity = len(data) // 2 if write_quantity is None else write_quantity
    byte_count = len(data) if byte_count is None else byte_count
    return struct.pack(">BHHHHB", 0x17, read_address, read_quantity, write_address, write_quantity,
                       byte_count & 0xFF) + data


# --- PDUs ------------------------------------------------------------------

VALID = {
    "fc3_status_9000_9003": fc3(reg(9000), 16),
    "fc3_result_100": fc3(reg(100), 4),
    "fc3_max_31_variables": fc3(reg(100), 124),
    "fc3_handshake_9000_9010": fc3(reg(9000), 44),
    "fc16_arg_1": fc16(reg(1), words(1.0)),
    "fc16_args_1_3": fc16(reg(1), words(1.0, -2.5, 3e3)),
    "fc16_g57_point": fc16(reg(5281), words(0.0, 0.0, 10.0)),
    "fc16_max_30_variables": fc16(reg(1), words(*range(30))),
    "fc23_read_9000_write_1": fc23(reg(9000), 4, reg(1), words(2.0)),
    "fc23_overlap_write_read_1": fc23(reg(1), 8, reg(1), words(4.0, 5.0)),
}

REFUSED = {
    "empty": b"",
    "fc_only_3": b"\x03",
    "fc6_single_register": struct.pack(">BHH", 0x06, reg(1), 1),
    "fc1_coils": struct.pack(">BHH", 0x01, 0, 8),
    "fc0x83_top_bit": struct.pack(">BHH", 0x83, reg(9000), 4),
    "fc0xff": b"\xff\x00\x00",
    "fc3_quantity_0": fc3(reg(9000), 0),
    "fc3_quantity_126": fc3(reg(100), 126),
    "fc3_misaligned": fc3(reg(9000) + 1, 4),
    "fc3_undefined_variable": fc3(reg(3000), 4),
    "fc3_past_0xffff": fc3(0xFFFE, 4),
    "fc3_over_long": fc3(reg(9000), 4) + b"\x00",
    "fc16_quantity_0": fc16(reg(1), b"", quantity=0, byte_count=0),
    "fc16_quantity_124": fc16(reg(1), bytes(248), quantity=124, byte_count=248),
    "fc16_read_only_100": fc16(reg(100), words(1.0)),
    "fc16_nan": fc16(reg(1), words(float("nan"))),
    "fc16_config_locked_500": fc16(reg(500), words(0.0)),
    "fc16_bad_unlock_code": fc16(reg(9004), words(1234.0)),
    # CVE-2019-14462 / 14463: counts that disagree with the frame.
    "cve_2019_14462_fc16_byte_count_over_length": fc16(reg(1), words(1.0)[:2], quantity=4, byte_count=8),
    "cve_2019_14462_fc16_byte_count_255": fc16(reg(1), words(1.0), quantity=4, byte_count=0xFF),
    "cve_2019_14462_fc16_byte_count_0": fc16(reg(1), words(1.0), quantity=4, byte_count=0),
    "cve_2019_14462_fc16_quantity_over_byte_count": fc16(reg(1), words(1.0), quantity=123, byte_count=8),
    "cve_2019_14462_fc16_header_only": struct.pack(">BHH", 0x10, reg(1), 4),
    "cve_2019_14463_fc23_byte_count_over_length": fc23(reg(9000), 4, reg(1), words(1.0)[:4], 4, 8),
    "cve_2019_14463_fc23_byte_count_255": fc23(reg(9000), 4, reg(1), words(1.0), 4, 0xFF),
    "cve_2019_14463_fc23_write_quantity_122": fc23(reg(9000), 4, reg(1), bytes(244), 122, 244),
    "cve_2019_14463_fc23_read_quantity_0xffff": fc23(reg(9000), 0xFFFF, reg(1), words(1.0)),
    # CVE-2022-0367: the write range of FC23 past the map.
    "cve_2022_0367_fc23_write_past_0xffff": fc23(reg(9000), 4, 0xFFFC, words(1.0)),
    "cve_2022_0367_fc23_write_121_at_0xff88": fc23(reg(9000), 4, 0xFF88, bytes(242), 121, 242),
    "cve_2022_0367_fc23_write_after_map": fc23(reg(9000), 4, reg(9990), words(1.0)),
    "cve_2022_0367_fc23_read_past_0xffff": fc23(0xFFF0, 125, reg(1), words(1.0)),
}

SEQUENCES = {
    # Unlock, set a configuration variable, lock: persistence through the store.
    "seq_unlock_config_lock": [fc16(reg(9004), words(float(UNLOCK_CODE))),
                               fc16(reg(500), words(-100.0)), fc3(reg(500), 8),
                               fc16(reg(9004), words(0.0))],
    # The three points of an inclined face, then macro 9810 (three-point level).
    "seq_level_9810": [fc16(reg(5281), words(0.0, 0.0, 10.0)), fc16(reg(5301), words(100.0, 0.0, 30.0)),
                       fc16(reg(5321), words(0.0, 100.0, 10.0)), fc16(reg(9000), words(9810.0)),
                       fc3(reg(9000), 16), fc3(reg(100), 124)],
    # A write while the macro runs (busy), then the results.
    "seq_busy_write": [fc16(reg(9000), words(9810.0)), fc16(reg(1), words(1.0)), fc3(reg(9000), 12)],
    "seq_wrong_codes_backoff": [fc16(reg(9004), words(1.0)), fc16(reg(9004), words(2.0)),
                                fc16(reg(9004), words(float(UNLOCK_CODE)))],
}


def core_input(pdus):
    return b"".join(bytes([len(p)]) + p for p in pdus)


# --- Modbus TCP ---------------------------------------------------------------

def mbap(tid, pdu, unit=1, protocol=0, length=None):
    length = len(pdu) + 1 if length is None else length
    return struct.pack(">HHHB", tid, protocol, length, unit) + pdu


def chunks(data, size):
    """The tcp_framer input: `data` sent in chunks of `size` bytes."""
    out = b""
    for at in range(0, len(data), size):
        part = data[at:at + size]
        out += bytes([len(part)]) + part
    return out


def tcp_seeds():
    seeds = {}
    for name, pdu in list(VALID.items()) + list(REFUSED.items()):
        if len(pdu) + 7 <= 255:
            seeds["frame_" + name] = chunks(mbap(1, pdu), 255)
    read = mbap(7, fc3(reg(9000), 4))
    write = mbap(8, fc16(reg(1), words(1.0)))
    seeds["pipelined_3"] = chunks(read + write + read, 255)
    seeds["split_every_byte"] = chunks(read + write, 1)
    seeds["split_header_3_4"] = chunks(read[:3], 3) + chunks(read[3:], 255)
    # Issue 8: an unknown function code whose length covers an FC16 frame.
    hidden = mbap(9, fc16(reg(1), words(7.0)))
    seeds["smuggled_fc16_in_unknown_fc"] = chunks(mbap(2, b"\x41" + hidden), 255)
    seeds["unknown_fc_body_then_read"] = chunks(mbap(3, b"\x41\x00\x01\x02") + read, 255)
    seeds["bad_protocol_id_then_write"] = chunks(mbap(4, fc3(reg(9000), 4), protocol=1) + write, 255)
    seeds["length_1"] = chunks(mbap(5, b"", length=1) + read, 255)
    seeds["length_255"] = chunks(mbap(5, b"\x03", length=255), 255)
    seeds["length_short_of_pdu"] = chunks(mbap(6, fc3(reg(9000), 4), length=3) + read, 255)
    seeds["largest_frame_fc16_123"] = chunks(mbap(10, fc16(reg(1), bytes(246), 123, 246)), 200)
    seeds["cve_2019_14462_mbap_short_fc16"] = chunks(
        mbap(11, fc16(reg(1), words(1.0)[:2], quantity=4, byte_count=8)), 255)
    seeds["cve_2022_0367_mbap_fc23"] = chunks(mbap(12, fc23(reg(9000), 4, 0xFFFC, words(1.0))), 255)
    seeds["sixteen_pipelined"] = chunks(b"".join(mbap(100 + i, fc3(reg(9000), 4)) for i in range(16)), 255)
    return seeds


# --- Storage image -------------------------------------------------------------

RECORDS = {"config": 0, "work_offsets": 1, "rigidity": 2, "gantry": 3, "spindle": 4}


def slot(record, which, sequence, payload, damage=0):
    """A keyed_store input slot (fuzz_keyed_store.cpp)."""
    return struct.pack(">BBIH", 2 * RECORDS[record] + which, damage, sequence, len(payload)) + payload


def variables(entries):
    return b"".join(struct.pack("<Hd", n, v) for n, v in entries)


def rigidity_table():
    poses = [-10.0, 0.0, 10.0]
    out = struct.pack("<HHHH", 1, len(poses), 1, 0)
    out += struct.pack("<10d", 0, 0, 0, 1, 0, 0, 0, 0, 0, 0)
    for a in poses:
        out += struct.pack("<d", a)
        out += struct.pack("<3d3d", 0, 0, 0, 0, 0, 0)      # rotvec, its sigma
        out += struct.pack("<5d", 0, 0, 0, 0, 0)           # rigidity, sigma, theta, a_error, sigma
        out += struct.pack("<3d3d", 0, 0, 0, 0, 0, 0)      # origin offset, C centre
        out += struct.pack("<3d3d", 0, 0, 1, 1, 0, 0)      # C direction, C x axis
        out += struct.pack("<3d", 0.001, 90.0, 8.0)        # rms, arc, count
    return out


def gantry_table():
    identity = [1, 0, 0, 0, 1, 0, 0, 0, 1]
    out = struct.pack("<HHI", 1, 0x01, 0)
    out += struct.pack("<18d", *identity, 0, 0, 0, 0.01, 0.01, 0.001, 1, 1, 1)
    sub = struct.pack("<B7x", 0) + struct.pack("<26d", *identity, 10, 20, 30, 0.001, 1, 1, 1, 2, 2, 2,
                                               0.5, 90.0, 0.01, 0.01, 0.01, 0.001, 0.001)
    return out + sub + bytes(7 * len(sub))


def spindle_model():
    out = struct.pack("<HHIIII I", 1, 0, 720, 360, 360, 12, 0)
    out += struct.pack("<9d", 0.1, 0.2, -50.0, 1e-4, -2e-4, 0.001, 0.002, 0.0, 0.0)
    covariance = [1e-8 if i == j else 0.0 for i in range(9) for j in range(i, 9)]
    out += struct.pack("<45d", *covariance)
    out += struct.pack("<3d", 100.0, 50.0, 150.0)
    out += struct.pack("<4d", 1e-4, 5e-5, 1e-4, 1e-3)
    assert len(out) == 512, len(out)
    return out


def store_seeds():
    config = variables([(500, -100.0), (501, 100.0), (900, 1234.0)])
    offsets = variables([(5221, 1.0), (5222, 2.0), (5223, 3.0), (5281, 0.0)])
    seeds = {
        "empty_image": b"\x01",
        "config_and_offsets": b"\x01" + slot("config", 0, 1, config) + slot("work_offsets", 1, 7, offsets),
        "config_two_slots_newer_second": b"\x01" + slot("config", 0, 5, config) +
        slot("config", 1, 6, variables([(500, 1.0)])),
        "config_sequence_wraps": b"\x01" + slot("config", 0, 0xFFFFFFFF, config) +
        slot("config", 1, 0, variables([(500, 2.0)])),
        "config_newest_damaged": b"\x01" + slot("config", 0, 1, config) +
        slot("config", 1, 2, variables([(500, 3.0)]), damage=0x01) + b"\x05",
        "config_nan_and_unknown_number": b"\x01" + slot("config", 0, 1, variables([(500, float("nan")),
                                                                                 (4242, 1.0), (502, 1e300)])),
        "config_length_over_capacity": b"\x01" + struct.pack(">BBIH", 0, 0, 1, 0xFFFF) + config,
        "config_other_version": b"\x01" + slot("config", 0, 1, config, damage=0x04) + b"\x00\x02",
        "rigidity_table": b"\x01" + slot("rigidity", 0, 1, rigidity_table()),
        "gantry_table": b"\x01" + slot("gantry", 0, 1, gantry_table()),
        "spindle_model": b"\x01" + slot("spindle", 1, 3, spindle_model()),
        "all_records": b"\x01" + slot("config", 0, 1, config) + slot("work_offsets", 0, 1, offsets) +
        slot("rigidity", 0, 1, rigidity_table()) + slot("gantry", 1, 1, gantry_table()) +
        slot("spindle", 0, 1, spindle_model()),
    }
    return seeds


def decoder_seeds():
    return {
        "rigidity_valid": b"\x00" + rigidity_table(),
        "gantry_valid": b"\x01" + gantry_table(),
        "spindle_valid": b"\x02" + spindle_model(),
        "rigidity_truncated": b"\x00" + rigidity_table()[:-1],
        "gantry_truncated": b"\x01" + gantry_table()[:100],
        "spindle_empty": b"\x02",
    }


# --- Modbus RTU ------------------------------------------------------------------

RTU_BAUDS = [1200, 2400, 9600, 19200, 19201, 38400, 57600, 115200]  # fuzz_rtu_framer.cpp kBauds
# Gap codes (bits 0..2 of an operation's code): when it happens after the last byte.
BACK_TO_BACK, ONE_CHARACTER, BELOW_SILENCE, AT_SILENCE, ABOVE_SILENCE, ONE_SECOND, SAME_INSTANT, \
    ONE_AND_HALF = range(8)
POLL = 0x08
SET_ADDRESS = 0x18


def crc16_modbus(data):
    """CRC-16/MODBUS, the specification's bit loop."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def rtu(address, pdu):
    """| address | PDU | CRC low, high |."""
    frame = bytes([address]) + pdu
    return frame + struct.pack("<H", crc16_modbus(frame))


def line(data, first=AT_SILENCE, rest=BACK_TO_BACK):
    """rtu_framer operations: the bytes of `data`, the first after `first`."""
    out = b""
    for i, byte in enumerate(data):
        out += bytes([first if i == 0 else rest, byte])
    return out


def rtu_input(*ops, baud=19200, address=1):
    return bytes([RTU_BAUDS.index(baud), address]) + b"".join(ops)


def poll(gap=AT_SILENCE):
    return bytes([POLL | gap])


def rtu_seeds():
    seeds = {}
    for name, pdu in VALID.items():
        seeds["frame_" + name] = rtu_input(line(rtu(1, pdu)), poll())
    for name in ("fc_only_3", "fc1_coils", "fc16_nan", "cve_2019_14462_fc16_byte_count_over_length",
                 "cve_2019_14463_fc23_read_quantity_0xffff", "cve_2022_0367_fc23_write_past_0xffff"):
        seeds["frame_" + name] = rtu_input(line(rtu(1, REFUSED[name])), poll())
    read = rtu(1, fc3(reg(9000), 4))
    write = rtu(1, fc16(reg(1), words(1.0)))
    fc23_write = fc23(reg(9000), 4, reg(1), words(2.0))
    seeds["broadcast_fc16_write"] = rtu_input(line(rtu(0, fc16(reg(1), words(5.0)))), poll())
    seeds["broadcast_fc3_read"] = rtu_input(line(rtu(0, fc3(reg(9000), 4))), poll())
    seeds["broadcast_fc23_read_write"] = rtu_input(line(rtu(0, fc23_write)), poll())
    seeds["broadcast_unknown_fc"] = rtu_input(line(rtu(0, b"\x41\x00\x01")), poll())
    seeds["broadcast_write_then_read"] = rtu_input(line(rtu(0, fc16(reg(1), words(6.0)))),
                                                   line(rtu(1, fc3(reg(1), 4))), poll())
    for to in (2, 247, 248, 255):
        seeds[f"other_address_{to}"] = rtu_input(line(rtu(to, fc16(reg(1), words(3.0)))), poll())
    seeds["slave_247"] = rtu_input(line(rtu(247, fc3(reg(9000), 4))), poll(), address=247)
    seeds["slave_0_is_1"] = rtu_input(line(rtu(1, fc3(reg(9000), 4))), poll(), address=0)
    seeds["set_address_17_then_read"] = rtu_input(bytes([SET_ADDRESS, 17, SET_ADDRESS, 248]),
                                                  line(rtu(17, fc3(reg(9000), 4))), poll(),
                                                  line(rtu(1, fc3(reg(9000), 4))), poll())
    bad = bytearray(write)
    bad[-1] ^= 0x01
    seeds["bad_crc_last_byte"] = rtu_input(line(bytes(bad)), poll())
    bad = bytearray(write)
    bad[0] ^= 0x01
    seeds["bad_crc_address_flipped"] = rtu_input(line(bytes(bad)), poll())
    seeds["crc_byte_order_swapped"] = rtu_input(line(write[:-2] + write[-1:] + write[-2:-1]), poll())
    seeds["too_short_1_2_3"] = rtu_input(line(b"\x01"), line(b"\x01\x03"), line(b"\x01\x03\x00"), poll())
    seeds["shortest_4_bytes"] = rtu_input(line(rtu(1, b"\x03")), poll())
    longest = rtu(1, b"\x41" + bytes([0xAA] * 252))
    assert len(longest) == 256
    seeds["longest_256_bytes"] = rtu_input(line(longest), poll())
    over = rtu(1, fc16(reg(1), words(8.0)) + bytes(255 - 1 - len(fc16(reg(1), words(8.0)))))
    assert len(over) == 257
    seeds["too_long_257_then_write"] = rtu_input(line(over), poll(), line(write), poll())
    seeds["too_long_300"] = rtu_input(line(bytes([0x55] * 300)), poll())
    for k in (1, 3, len(write) - 2, len(write) - 1):
        seeds[f"split_before_{k}_below_silence"] = rtu_input(
            line(write[:k]), line(write[k:], first=BELOW_SILENCE), poll())
        seeds[f"split_before_{k}_at_silence"] = rtu_input(
            line(write[:k]), line(write[k:], first=AT_SILENCE), poll())
    seeds["split_one_and_half_characters"] = rtu_input(line(write, rest=ONE_AND_HALF), poll())
    seeds["split_one_character"] = rtu_input(line(write, rest=ONE_CHARACTER), poll())
    seeds["fifo_burst_same_instant"] = rtu_input(line(write, rest=SAME_INSTANT), poll())
    seeds["back_to_back_at_silence"] = rtu_input(line(write), line(read), line(write), poll())
    seeds["back_to_back_above_silence"] = rtu_input(line(write), line(read, first=ABOVE_SILENCE), poll())
    seeds["back_to_back_below_silence"] = rtu_input(line(write), line(read, first=BELOW_SILENCE), poll())
    seeds["back_to_back_one_second"] = rtu_input(line(write), line(read, first=ONE_SECOND), poll(ONE_SECOND))
    seeds["poll_below_then_at_silence"] = rtu_input(line(read), poll(BELOW_SILENCE), poll(AT_SILENCE),
                                                    poll(ABOVE_SILENCE))
    seeds["poll_mid_frame"] = rtu_input(line(read[:4]), poll(BACK_TO_BACK), poll(ONE_CHARACTER),
                                        line(read[4:], first=BACK_TO_BACK), poll())
    seeds["no_final_poll"] = rtu_input(line(read))
    unlock = [fc16(reg(9004), words(float(UNLOCK_CODE))), fc16(reg(500), words(-100.0)), fc3(reg(500), 8),
              fc16(reg(9004), words(0.0))]
    seeds["seq_unlock_config_lock"] = rtu_input(*[line(rtu(1, p)) for p in unlock], poll())
    level = SEQUENCES["seq_level_9810"]
    seeds["seq_level_9810"] = rtu_input(*[line(rtu(1, p)) + poll() for p in level],
                                        *[poll(ONE_SECOND) for _ in range(8)], line(rtu(1, fc3(reg(9000), 16))),
                                        poll())
    for baud in (1200, 9600, 38400, 115200):
        seeds[f"baud_{baud}_split_at_silence"] = rtu_input(
            line(write), line(read[:3]), line(read[3:], first=BELOW_SILENCE), line(read, first=AT_SILENCE),
            poll(BELOW_SILENCE), poll(), baud=baud)
    return seeds


def write(target, seeds):
    directory = os.path.join(CORPUS, target)
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    for name, data in sorted(seeds.items()):
        with open(os.path.join(directory, name), "wb") as f:
            f.write(data)
    print(f"{target}: {len(seeds)} seeds")


def main():
    core = {name: core_input([pdu]) for name, pdu in list(VALID.items()) + list(REFUSED.items())}
    core.update({name: core_input(pdus) for name, pdus in SEQUENCES.items()})
    core["all_refused_in_a_row"] = core_input(list(REFUSED.values())[:16])
    write("modbus_core", core)
    write("tcp_framer", tcp_seeds())
    write("keyed_store", store_seeds())
    write("table_decoders", decoder_seeds())
    write("rtu_framer", rtu_seeds())


if __name__ == "__main__":
    main()
