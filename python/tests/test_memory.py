"""Calls the process cannot hold raise MemoryError before they allocate, where
an allocation failure would kill the interpreter."""

import subprocess
import sys
import textwrap

import pytest


def run_limited(code: str, gigabytes: float) -> subprocess.CompletedProcess:
    """Runs `code` in a fresh interpreter whose address space is limited."""
    limit = int(gigabytes * 2**30)
    prelude = textwrap.dedent(
        f"""
        import resource
        resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
        import numpy as np
        import pixgeo
        """
    )
    return subprocess.run(
        [sys.executable, "-c", prelude + textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=120,
    )


@pytest.mark.parametrize(
    "call",
    [
        "pixgeo.voronoi(np.array([[1.0, 2.0], [50.0, 70.0]]), (100000, 100000))",
        "pixgeo.distance_transform_edt(np.ones((30000, 30000), dtype=bool))",
        "pixgeo.natural_neighbor(np.array([[0.0, 0], [1, 0], [0, 1]]), np.zeros(3), (20000, 20000))",
        # 1.2 GB of sites the interpreter holds; their work would take 25 GB.
        "pixgeo.power_diagram(np.zeros((50_000_000, 2)), np.zeros(50_000_000), (64, 64))",
    ],
)
def test_work_beyond_the_address_space_raises_memory_error(call):
    done = run_limited(
        f"""
        try:
            {call}
        except MemoryError as e:
            assert "needs about" in str(e), e
            print("refused")
        """,
        gigabytes=6,
    )
    assert done.returncode == 0 and done.stdout.strip() == "refused", done.stderr
