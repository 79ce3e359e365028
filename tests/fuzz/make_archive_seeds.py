#!/usr/bin/env python3
"""Writes the seeds of fuzz_archive: small archives as `tern import` takes them (.zip, .tar.gz), made
with Python's zipfile and tarfile. The good ones hold an ALFA-like directory (one directory per
sequence, <bag>-mavros-<topic>.csv members: the first lines of the ALFA CSVs in
tests/fuzz/corpus/fuzz_text_table); the hostile ones hold what ArchiveInput must refuse: a symlink
member (to /etc/passwd, and standing in for the raw IMU), a hard link, a character device, a FIFO,
a `../` name, an absolute name, a directory without the owner's write permission, a GNU sparse
member declaring 1 GiB, and a bzip2 bomb (17 MiB of zeros in 100-odd bytes, above the fuzzer's
16 MiB limit). regression_readonly_dir and regression_sparse_1gib failed the target before
ArchiveInput set the members' permissions and counted a member's declared size (its holes).

  make_archive_seeds.py OUT_DIR
"""
import bz2
import gzip
import io
import os
import sys
import tarfile
import zipfile

from seed_files import write_seeds

HERE = os.path.dirname(os.path.abspath(__file__))
TEXT = os.path.join(HERE, "corpus", "fuzz_text_table")
BAG = "carbonZ_2018-07-18-15-53-31_1_engine_failure"


def alfa_members():
    """(name, bytes) of an ALFA-like sequence directory, from the text-table seeds."""
    out = []
    for topic in ("imu-data_raw", "imu-atm_pressure", "global_position-raw-fix"):
        with open(os.path.join(TEXT, f"alfa_{topic}.csv"), "rb") as f:
            data = f.read()
        out.append((f"{BAG}/{BAG}-mavros-{topic}.csv", data[:600]))
    return out


def tar_bytes(mode, entries):
    """entries: (TarInfo, bytes or None); mode "w:gz" or "w:bz2" (gzip without a time stamp: the
    same seeds every run)."""
    buf = io.BytesIO()
    with tarfile.open(fileobj=buf, mode="w", format=tarfile.PAX_FORMAT) as t:
        for info, data in entries:
            t.addfile(info, io.BytesIO(data) if data is not None else None)
    return gzip.compress(buf.getvalue(), mtime=0) if mode == "w:gz" else bz2.compress(buf.getvalue())


def regular(name, data, mode=0o644):
    info = tarfile.TarInfo(name)
    info.size, info.mode, info.mtime = len(data), mode, 1531929211
    return info, data


def special(name, kind, **fields):
    info = tarfile.TarInfo(name)
    info.type, info.mode, info.mtime = kind, 0o644, 1531929211
    for k, v in fields.items():
        setattr(info, k, v)
    return info, None


def directory(name, mode=0o755):
    info = tarfile.TarInfo(name)
    info.type, info.mode, info.mtime = tarfile.DIRTYPE, mode, 1531929211
    return info, None


def zip_bytes(entries, symlink=None):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in entries:
            z.writestr(zipfile.ZipInfo(name, (2018, 7, 18, 15, 53, 31)), data, zipfile.ZIP_DEFLATED)
        if symlink:  # a Unix symlink as Info-ZIP stores it: mode S_IFLNK in the external attributes, the target as data
            info = zipfile.ZipInfo(symlink[0], (2018, 7, 18, 15, 53, 31))
            info.create_system = 3
            info.external_attr = (0o120777 << 16)
            z.writestr(info, symlink[1])
    return buf.getvalue()


def sparse_member(name, real_size):
    """A GNU sparse 1.0 member (pax headers): one 13-byte data block at 0, then a hole to real_size."""
    data = b"t [s],stamp\n0"
    sparse_map = f"1\n0\n{len(data)}\n".encode()
    body = sparse_map.ljust(512, b"\0") + data
    info = tarfile.TarInfo(f"{os.path.dirname(name)}/GNUSparseFile.0/{os.path.basename(name)}")
    info.size, info.mode, info.mtime = len(body), 0o644, 1531929211
    info.pax_headers = {"GNU.sparse.major": "1", "GNU.sparse.minor": "0", "GNU.sparse.name": name,
                        "GNU.sparse.realsize": str(real_size)}
    return info, body


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    alfa = alfa_members()
    raw_imu = alfa[0][0]
    seeds = {
        "alfa.zip": zip_bytes(alfa),
        "alfa.tar.gz": tar_bytes("w:gz", [directory(BAG)] + [regular(n, d) for n, d in alfa]),
        # the raw IMU a symlink (to /etc/passwd): refused, never replaced by the filtered IMU
        "symlink_raw_imu.tar.gz": tar_bytes("w:gz", [regular(n, d) for n, d in alfa[1:]] +
                                            [special(raw_imu, tarfile.SYMTYPE, linkname="/etc/passwd")]),
        "symlink_raw_imu.zip": zip_bytes(alfa[1:], symlink=(raw_imu, "/etc/passwd")),
        "hardlink.tar.gz": tar_bytes("w:gz", [regular(n, d) for n, d in alfa[1:]] +
                                     [special(raw_imu, tarfile.LNKTYPE, linkname=alfa[1][0])]),
        "device.tar.gz": tar_bytes("w:gz", [special(raw_imu, tarfile.CHRTYPE, devmajor=1, devminor=5)]),
        "fifo.tar.gz": tar_bytes("w:gz", [special(raw_imu, tarfile.FIFOTYPE)]),
        "dotdot.tar.gz": tar_bytes("w:gz", [regular(f"{BAG}/../../escaped.csv", alfa[0][1])]),
        "dotdot.zip": zip_bytes([(f"../{BAG}-mavros-imu-data_raw.csv", alfa[0][1])]),
        "absolute.tar.gz": tar_bytes("w:gz", [regular("/tmp/tern-fuzz-absolute.csv", alfa[0][1])]),
        "regression_readonly_dir.tar.gz": tar_bytes("w:gz", [directory(BAG, 0o555)] + [regular(n, d) for n, d in alfa]),
        "regression_sparse_1gib.tar.gz": tar_bytes("w:gz", [sparse_member(raw_imu, 1 << 30)]),
        "bomb.tar.bz2": tar_bytes("w:bz2", [regular(raw_imu, bytes(17 << 20))]),
    }
    write_seeds(out, seeds)


if __name__ == "__main__":
    main()
