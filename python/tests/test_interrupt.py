"""Ctrl-C reaches a long call: the work stops at its next submission to the
device and the call raises KeyboardInterrupt soon after."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import pixgeo


def test_ctrl_c_interrupts_a_long_call():
    sites = np.array([[10.0, 10.0], [2900.0, 2500.0]])
    sent = []

    def interrupt():
        time.sleep(0.5)
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt).start()
    with pytest.raises(KeyboardInterrupt):
        pixgeo.settle(sites, (3000, 3000))
    # Measured at 0.1 to 0.6 s; before, the call ran to its end (about 50 s).
    assert sent and time.monotonic() - sent[0] < 5.0
    # The device works again afterwards.
    assert pixgeo.voronoi(sites, (16, 16)).labels.shape == (16, 16)
