"""A communication model plugin: log-distance path loss, shadowing, and a packet
error rate that grows with distance.

How radio engineers model a low-power link (Rappaport, *Wireless Communications*,
§4.9-4.11; Zuniga & Krishnamachari, "Analyzing the transitional region in low power
wireless links", IEEE SECON 2004):

* path loss at distance ``d`` metres, in dB:
  ``PL(d) = PL(d0) + 10 n log10(d / d0) + X``, with ``X ~ Normal(0, sigma)`` the
  log-normal shadowing;
* signal-to-noise ratio at the receiver: ``SNR = P_t - PL(d) - P_n`` (dB);
* bit error rate of non-coherent FSK: ``p_b = 1/2 exp(-(SNR_linear * B_N/R) / 2)``;
* a packet of ``L`` bytes arrives with probability ``(1 - p_b) ** (8 L)``, so the
  packet error rate ``PER = 1 - (1 - p_b) ** (8 L)`` grows with distance (and with
  the packet's length): near robots hear each other almost surely, far ones rarely,
  with a "transitional region" in between.

Two robots are linked (same sub-network, relays work) when their SNR is at least
``min_snr_db``; every reception over a link is then lost with its PER. The shadowing
``X`` of each pair of robots is drawn again at every tick from the run's
communication stream (the robots move, so what stands between them changes).
Bandwidth, latency and ``--loss`` (extra random loss) work as with the built-in
``network`` model, which this model extends; ``--comm-range`` and ``--comm-los`` are
refused: the link budget decides who hears whom.

Parameters (``--comm KEY=VALUE``)
---------------------------------

==============  =============  ===========  =====  ==========================================
symbol          name           default      unit   meaning
==============  =============  ===========  =====  ==========================================
``n``           exponent       3.0                 path-loss exponent (2 in free space,
                                                   about 3 indoors)
``PL(d0)``      pl_d0_db       55.0         dB     path loss at the reference distance
``d0``          d0_m           1.0          m      reference distance
``sigma``       shadowing_db   4.0          dB     standard deviation of the shadowing
``P_t``         tx_power_dbm   0.0          dBm    transmit power
``P_n``         noise_dbm      -105.0       dBm    noise floor
``B_N/R``       bn_over_r      1.5625              noise bandwidth over bit rate (30 kHz /
                                                   19.2 kbit/s: a Mica2 CC1000 radio)
\\               min_snr_db     6.0          dB     weakest SNR that still counts as a link
\\               cell_m         1.0          m      metres per cell for maps without a
                                                   resolution
==============  =============  ===========  =====  ==========================================

With the defaults the mean SNR is 50 - 30 log10(d) dB, and a 100-byte message
(before shadowing) crosses 20 m with probability 0.98, 22 m with 0.77, 25 m with 0.07;
links reach about 29 m.

Install it as a package whose metadata names it in the entry-point group
``mrexplore.comm`` (see ``pyproject.toml`` beside this file), then::

    mrexplore comm-models
    mrexplore run --map sheng40 --robots 4 --comm-model log-distance --comm exponent=3.5
    python -c "from mrexplore.checks import check_comm_model; check_comm_model('log-distance')"
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from mrexplore.comm.channels import Channel, Delayed, Lossy, Perfect
from mrexplore.comm.links import Link, LinkModel
from mrexplore.comm.models import CommSetup, Network
from mrexplore.errors import ScenarioError
from mrexplore.params import Param

Cell = tuple[int, int]


def mean_snr_db(
    distance_m: float,
    *,
    exponent: float,
    pl_d0_db: float,
    d0_m: float,
    tx_power_dbm: float,
    noise_dbm: float,
) -> float:
    """Mean SNR (dB) at ``distance_m`` metres: ``P_t - PL(d) - P_n`` without shadowing
    (closer than ``d0`` counts as ``d0``).

    >>> round(mean_snr_db(10.0, exponent=3.0, pl_d0_db=55.0, d0_m=1.0,
    ...                   tx_power_dbm=0.0, noise_dbm=-105.0), 6)
    20.0
    """
    path_loss = pl_d0_db + 10.0 * exponent * math.log10(max(distance_m, d0_m) / d0_m)
    return tx_power_dbm - path_loss - noise_dbm


def packet_success(snr_db: float, n_bytes: int, bn_over_r: float) -> float:
    """Probability that ``n_bytes`` arrive intact at ``snr_db`` (non-coherent FSK):
    ``(1 - 1/2 exp(-SNR B_N/R / 2)) ** (8 n_bytes)``; the PER is one minus this.

    >>> round(packet_success(10.0, 100, 1.5625), 2)
    0.85
    """
    bit_error = 0.5 * math.exp(-(10.0 ** (snr_db / 10.0)) * bn_over_r / 2.0)
    return (1.0 - bit_error) ** (8 * n_bytes)


class LogDistanceLinks(LinkModel):
    """Links where the SNR (with this tick's shadowing) reaches ``min_snr_db``; each
    reception over a link succeeds with :func:`packet_success`."""

    lossy = True

    def __init__(self, *, metres_per_cell: float, rng: np.random.Generator, **radio: float) -> None:
        self.metres_per_cell = metres_per_cell
        self.rng = rng
        self.radio = radio
        self._snr_db: dict[Link, float] = {}

    def links(self, positions: Mapping[int, Cell]) -> frozenset[Link]:
        ids = sorted(positions)
        pairs = [(a, b) for i, a in enumerate(ids) for b in ids[i + 1 :]]
        # one draw per pair of live robots, near or far: the stream's use does not
        # depend on where the robots are
        shadowing = self.rng.normal(0.0, self.radio["shadowing_db"], len(pairs))
        self._snr_db = {}
        for (a, b), extra_loss in zip(pairs, shadowing, strict=True):
            (row_a, col_a), (row_b, col_b) = positions[a], positions[b]
            distance_m = math.hypot(row_a - row_b, col_a - col_b) * self.metres_per_cell
            snr = self.mean_snr(distance_m) - float(extra_loss)
            if snr >= self.radio["min_snr_db"]:
                self._snr_db[(a, b)] = snr
        return frozenset(self._snr_db)

    def mean_snr(self, distance_m: float) -> float:
        r = self.radio
        return mean_snr_db(
            distance_m,
            exponent=r["exponent"],
            pl_d0_db=r["pl_d0_db"],
            d0_m=r["d0_m"],
            tx_power_dbm=r["tx_power_dbm"],
            noise_dbm=r["noise_dbm"],
        )

    def delivery_probability(self, transmitter: int, receiver: int, n_bytes: int) -> float:
        snr = self._snr_db.get((min(transmitter, receiver), max(transmitter, receiver)))
        return 0.0 if snr is None else packet_success(snr, n_bytes, self.radio["bn_over_r"])

    def describe(self) -> str:
        r = self.radio
        return (
            f"log-distance n={r['exponent']:g}, PL(d0)={r['pl_d0_db']:g} dB at "
            f"{r['d0_m']:g} m, shadowing {r['shadowing_db']:g} dB, P_t={r['tx_power_dbm']:g} "
            f"dBm, P_n={r['noise_dbm']:g} dBm, links from SNR {r['min_snr_db']:g} dB, "
            f"{self.metres_per_cell:g} m per cell"
        )


class LogDistanceRadio(Network):
    """Log-distance path loss with shadowing; packet error rate from the SNR."""

    id = "log-distance"
    summary = (
        "log-distance path loss + log-normal shadowing; links from an SNR threshold, "
        "each reception lost with the packet error rate of its SNR and length"
    )
    params: ClassVar[Mapping[str, Param]] = {
        "exponent": Param(3.0, "", "path-loss exponent", "n", low=1.0, high=10.0),
        "pl_d0_db": Param(55.0, "dB", "path loss at the reference distance", "PL(d0)", low=0),
        "d0_m": Param(1.0, "m", "reference distance", "d0", low=0, low_open=True),
        "shadowing_db": Param(4.0, "dB", "shadowing standard deviation", "sigma", low=0),
        "tx_power_dbm": Param(0.0, "dBm", "transmit power", "P_t", low=-60, high=40),
        "noise_dbm": Param(-105.0, "dBm", "noise floor", "P_n", low=-200, high=0),
        "bn_over_r": Param(
            1.5625, "", "noise bandwidth over bit rate", "B_N/R", low=0, low_open=True
        ),
        "min_snr_db": Param(6.0, "dB", "weakest SNR that still counts as a link"),
        "cell_m": Param(
            1.0, "m", "metres per cell for maps without a resolution", low=0, low_open=True
        ),
    }

    @classmethod
    def from_setup(cls, setup: CommSetup, **params: Any) -> LogDistanceRadio:
        if not math.isinf(setup.comm_range) or setup.comm_los:
            raise ScenarioError(
                "--comm-model log-distance: the link budget decides who hears whom; "
                "leave out --comm-range and --comm-los (tune --comm exponent=..., "
                "min_snr_db=...)"
            )
        metres_per_cell = setup.metres_per_cell or params["cell_m"]
        radio = {k: float(v) for k, v in params.items() if k != "cell_m"}
        links = LogDistanceLinks(metres_per_cell=metres_per_cell, rng=setup.rng, **radio)
        channel: Channel = Perfect()
        if setup.latency != 1:
            channel = Delayed(channel, setup.latency)
        if setup.loss > 0:
            channel = Lossy(channel, setup.loss, setup.rng)
        return cls(setup.n_robots, links, channel=channel, bandwidth=setup.bandwidth, rng=setup.rng)
