"""The estimate that refuses jobs out of reach before any work."""

import pytest

from csql_sim.infra.errors import CsqlError
from csql_sim.learners.training.costs import GB, check_fits, estimate, parse_size


def test_six_blocks_sharded_fit_a_few_gigabytes_and_one_engine_does_not():
    sharded = estimate("cs-ql", 6, 64, 2)
    whole = estimate("cs-ql", 6, 1, 1, sharded=True)
    assert sharded.pairs == 7057 * 7056 == 49_794_192
    assert 1 * GB < sharded.peak_bytes < 4 * GB
    assert whole.peak_bytes > 16 * GB  # every goal in one engine
    assert sharded.seconds < 30 * 60


def test_more_workers_cost_memory_and_save_time():
    two, four = estimate("cs-ql", 6, 64, 2), estimate("cs-ql", 6, 64, 4)
    assert four.peak_bytes > two.peak_bytes and four.seconds < two.seconds


def test_limits_refuse_with_one_line(tmp_path):
    est = estimate("cs-ql", 6, 64, 2)
    assert check_fits(est, tmp_path / "r6", max_memory=64 * GB) is None
    line = check_fits(est, tmp_path / "r6", max_memory=GB)
    assert line is not None and "\n" not in line and "1.0 GB" in line and "--backend ray" in line
    seven = check_fits(estimate("cs-ql", 7, 512, 2), tmp_path / "r7", max_memory=1 << 50)
    assert seven is not None and "6 blocks" in seven and "--force" not in seven  # whatever the machine


@pytest.mark.parametrize("text, value", [("1G", GB), ("512M", 512 << 20), ("1.5g", int(1.5 * GB)), ("4GiB", 4 * GB),
                                         ("2000000", 2_000_000)])
def test_sizes_parse(text, value):
    assert parse_size(text) == value


@pytest.mark.parametrize("text", ["", "lots", "-1G", "0", "nanG", "1e30T", "1000", "1e-9G"])
def test_bad_sizes_are_refused(text):
    with pytest.raises(CsqlError, match="--max-memory"):
        parse_size(text)
