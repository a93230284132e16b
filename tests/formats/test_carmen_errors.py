"""CARMEN log read errors: one line naming the file (and the line), whatever the damage."""
from __future__ import annotations

import gzip

import pytest

from slam_predict.errors import InputError
from slam_predict.formats.carmen import read_log

ODOM = "ODOM {x} 0.0 0.0 0.0 0.0 0.0 {t} host {t}\n"


def plain_log(count: int) -> str:
    return "".join(ODOM.format(x=0.1 * i, t=float(i)) for i in range(count))


def test_gzip_members_and_crlf_read_like_plain(tmp_path):
    text = plain_log(20)
    plain = tmp_path / "a.log"
    plain.write_text(text.replace("\n", "\r\n"), newline="")
    two = tmp_path / "b.log.gz"
    two.write_bytes(gzip.compress(text[:300].encode()) + gzip.compress(text[300:].encode()))
    a, b = read_log(plain), read_log(two)
    assert len(a.odometry) == len(b.odometry) == 20
    assert (a.odometry.poses == b.odometry.poses).all()


def test_gz_name_without_gzip_data(tmp_path):
    path = tmp_path / "x.log.gz"
    path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(InputError) as info:
        read_log(path)
    assert info.value.one_line() == f"{path}: not a gzip file (the name ends in .gz but the " \
                                    "content is not gzip data)"


def test_corrupt_gzip(tmp_path):
    path = tmp_path / "x.log"
    path.write_bytes(b"\x1f\x8b\x08garbage after the magic")
    with pytest.raises(InputError, match=r"x\.log: not a gzip file or corrupt gzip data"):
        read_log(path)


def test_truncated_gzip_names_the_line(tmp_path):
    data = gzip.compress(plain_log(3000).encode())
    path = tmp_path / "x.log.gz"
    path.write_bytes(data[:len(data) // 2])
    with pytest.raises(InputError) as info:
        read_log(path)
    assert info.value.line is not None and 1 < info.value.line < 3000
    assert "truncated gzip file: the data stops inside line" in info.value.problem


def test_binary_content_names_the_line(tmp_path):
    path = tmp_path / "x.log"
    path.write_bytes(plain_log(3).encode() + b"ODOM \xff\xfe\n")
    with pytest.raises(InputError) as info:
        read_log(path)
    assert info.value.one_line() == f"{path}:4: not a CARMEN text log: byte 0xff is not UTF-8 " \
                                    "text"


def test_truncated_line_before_the_last_names_it(tmp_path):
    lines = plain_log(5).splitlines(keepends=True)
    lines[2] = "ODOM 1.0 2.0\n"
    path = tmp_path / "x.log"
    path.write_text("".join(lines))
    with pytest.raises(InputError, match=r"x\.log:3: ODOM line has too few fields"):
        read_log(path)
