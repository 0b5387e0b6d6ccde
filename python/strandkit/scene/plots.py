"""The run's picture: energies against time, and the drive's force against
its displacement (or torque against turns) when the protocol has a drive."""
from __future__ import annotations

import numpy as np

UNITS = {"si": ("s", "J", "m", "N", "N·m"), "molecular": ("ns", "pN·nm", "nm", "pN", "pN·nm")}


def plot_observables(obs, path: str, title: str = "", units: str = "si") -> str:
    """Writes the PNG at ``path`` (matplotlib, Agg) and returns the path."""
    import matplotlib.pyplot as plt

    from .._files import temporary_for
    t_u, e_u, x_u, f_u, m_u = UNITS.get(units, UNITS["si"])
    pulled = np.isfinite(obs["drive_force"]).any()
    turned = np.isfinite(obs["drive_torque"]).any()
    n = 1 + int(pulled) + int(turned)
    fig, axes = plt.subplots(1, n, figsize=(5.2 * n, 4), squeeze=False)
    ax = axes[0][0]
    ax.plot(obs["time"], obs["kinetic"], label="kinetic")
    ax.plot(obs["time"], obs["elastic"], label="elastic")
    if len(obs["total"]):  # the total's change: gravity's potential would flatten the others
        ax.plot(obs["time"], obs["total"] - obs["total"][0], label="total − its start")
    ax.set_xlabel(f"time ({t_u})")
    ax.set_ylabel(f"energy ({e_u})")
    ax.legend()
    j = 1
    if pulled:
        m = np.isfinite(obs["drive_force"])
        axes[0][j].plot(obs["drive_displacement"][m], obs["drive_force"][m], ".-")
        axes[0][j].set_xlabel(f"drive displacement ({x_u})")
        axes[0][j].set_ylabel(f"drive force ({f_u})")
        j += 1
    if turned:
        m = np.isfinite(obs["drive_torque"])
        axes[0][j].plot(obs["drive_turns"][m], obs["drive_torque"][m], ".-")
        axes[0][j].set_xlabel("turns")
        axes[0][j].set_ylabel(f"torque ({m_u})")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    with temporary_for(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path
