"""Unit systems for strandkit worlds.

The equations are the same in any consistent system of units; the only
constant the core needs is Boltzmann's, for thermal noise, and it takes it
from ``World(units=...)``:

* ``"si"`` (default): metre, kilogram, second; force N, energy J,
  viscosity Pa·s.
* ``"molecular"``: nanometre, piconewton, nanosecond; energy pN·nm
  (kT = 4.116 pN·nm at 298.15 K, 4.114 at 298 K), mass 1e-21 kg (attogram, ag), modulus
  pN/nm² (= 1 MPa), viscosity pN·ns/nm² (= 1e-3 Pa·s: water is 1.0),
  density ag/nm³ (= 1e6 kg/m³).

>>> import strandkit as sk
>>> round(sk.units.kT(298.15, "molecular"), 3)   # pN·nm
4.116
>>> sk.units.to_molecular(1.0e-3, "viscosity")   # water, Pa·s -> pN·ns/nm²
1.0
>>> world = sk.World(units="molecular", temperature=298.15,
...                  viscosity=sk.units.WATER_VISCOSITY["molecular"], dt=1e-3)
"""
from __future__ import annotations

__all__ = ["BOLTZMANN", "WATER_VISCOSITY", "kT", "to_molecular", "to_si", "SI_PER_MOLECULAR"]

#: Boltzmann's constant per unit system (energy unit per kelvin; exact SI value).
BOLTZMANN = {"si": 1.380649e-23, "molecular": 1.380649e-23 * 1e21}

#: Viscosity of water at 20 °C in each system (Pa·s; pN·ns/nm²); at 25 °C
#: it is 0.89e-3 Pa·s.
WATER_VISCOSITY = {"si": 1.0e-3, "molecular": 1.0}

#: One molecular unit of each quantity in SI units.
SI_PER_MOLECULAR = {
    "length": 1e-9,  # nm in m
    "force": 1e-12,  # pN in N
    "time": 1e-9,  # ns in s
    "energy": 1e-21,  # pN·nm in J
    "mass": 1e-21,  # pN·ns²/nm in kg
    "viscosity": 1e-3,  # pN·ns/nm² in Pa·s
    "modulus": 1e6,  # pN/nm² in Pa
    "density": 1e6,  # ag/nm³ in kg/m³
    "velocity": 1.0,  # nm/ns in m/s
    "torque": 1e-21,  # pN·nm in N·m
    "stiffness": 1e-3,  # pN/nm in N/m
    "bending_stiffness": 1e-30,  # pN·nm² in N·m²
    "drag": 1e-12,  # pN·ns/nm (force per velocity) in N·s/m
    "drag_per_length": 1e-3,  # pN·ns/nm² (force per velocity per length, as η) in N·s/m²
    "roll_drag": 1e-21,  # pN·ns (torque per angular velocity per length) in N·s
}


def _factor(quantity: str) -> float:
    try:
        return SI_PER_MOLECULAR[quantity]
    except KeyError:
        raise ValueError(f"unknown quantity {quantity!r}; known: {', '.join(sorted(SI_PER_MOLECULAR))}") from None


def kT(temperature: float = 298.15, units: str = "si") -> float:
    """Thermal energy k_B T (J in SI, pN·nm in molecular units) at
    ``temperature`` kelvin."""
    if units not in BOLTZMANN:
        raise ValueError(f"unknown units {units!r}; use 'si' or 'molecular'")
    if not temperature >= 0.0 or temperature == float("inf"):
        raise ValueError(f"temperature must be finite and >= 0 K, got {temperature}")
    return BOLTZMANN[units] * temperature


def to_molecular(value, quantity: str):
    """An SI value (scalar or numpy array) of ``quantity`` in molecular units."""
    return value / _factor(quantity)


def to_si(value, quantity: str):
    """A molecular-unit value of ``quantity`` in SI units."""
    return value * _factor(quantity)
