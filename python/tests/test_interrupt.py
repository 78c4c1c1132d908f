"""Ctrl-C reaches a long call: the work stops at its next submission to the
device and the call raises KeyboardInterrupt soon after."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import pixgeo


def interrupt_soon(sent):
    """Sends this process SIGINT in half a second, noting when."""

    def interrupt():
        time.sleep(0.5)
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=interrupt).start()


def test_ctrl_c_interrupts_a_long_call():
    sites = np.array([[10.0, 10.0], [2900.0, 2500.0]])
    sent = []
    interrupt_soon(sent)
    with pytest.raises(KeyboardInterrupt):
        pixgeo.settle(sites, (3000, 3000))
    # Measured at 0.1 to 0.6 s; before, the call ran to its end (about 50 s).
    assert sent and time.monotonic() - sent[0] < 5.0
    # The device works again afterwards.
    assert pixgeo.voronoi(sites, (16, 16)).labels.shape == (16, 16)


def test_ctrl_c_interrupts_work_on_the_cpu():
    # A 10000² transform runs on the CPU alone (about 2 s here): it looks at
    # its flag between rows. Before, Ctrl-C waited for its end.
    features = np.ones((10000, 10000), dtype=bool)
    features[::997, ::991] = False
    sent = []
    interrupt_soon(sent)
    with pytest.raises(KeyboardInterrupt):
        pixgeo.distance_transform_edt(features)
    # Measured at about 0.5 s.
    assert sent and time.monotonic() - sent[0] < 5.0
    small = np.ones((3, 3), dtype=bool)
    small[1, 1] = False
    assert pixgeo.distance_transform_edt(small)[0, 0] == pytest.approx(2**0.5)
