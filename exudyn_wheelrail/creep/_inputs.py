"""Input checks shared by every creep law of the package (one contract, one validation)."""
from __future__ import annotations

from ..validation import finite  # noqa: F401  (the package's one finiteness check, re-exported for the creep laws)


def check_contact_inputs(a, b, xi, eta, phi, normal_force, mu, shear_modulus):
    """Validate the common arguments of the creep-law contract: ``(a, b, xi, eta, phi, N, mu, G)`` as floats.

    Raises ``ValueError`` for non-finite values, semi-axes <= 0, N < 0, μ < 0 or G <= 0."""
    a = finite("a", a)
    b = finite("b", b)
    if a <= 0.0 or b <= 0.0:
        raise ValueError(f"semi-axes must be > 0, got a={a}, b={b}")
    xi = finite("xi", xi)
    eta = finite("eta", eta)
    phi = finite("phi", phi)
    N = finite("normal_force", normal_force)
    if N < 0.0:
        raise ValueError(f"normal_force must be >= 0, got {N}")
    mu = finite("mu", mu)
    if mu < 0.0:
        raise ValueError(f"mu must be >= 0, got {mu}")
    G = finite("shear_modulus", shear_modulus)
    if G <= 0.0:
        raise ValueError(f"shear_modulus must be > 0, got {G}")
    return a, b, xi, eta, phi, N, mu, G
