"""An independent float64 NumPy reference for brdfpy (the *oracle* the tests compare against).

Written from the course notes in ``shared/seeds`` and the published papers they cite, not from the
Rust sources: where a formula has more than one standard formulation, the oracle deliberately uses a
different one from the usual renderer form (e.g. exact dielectric Fresnel in Cook & Torrance's
``g``/``c`` form, conductor Fresnel in complex arithmetic, Oren-Nayar with explicit angles, Beckmann
written with ``tan^2``), so that a shared slip is unlikely.

Nothing here imports ``brdfpy``. Everything is float64 and vectorised over a leading axis.

Modules
-------
vectors    normalisation, reflect / refract / halfway, shading frames
fresnel    dielectric (g/c form and s/p angle form), conductor (complex), Schlick, F0 <-> IOR, metals
microfacet D terms (Beckmann, GGX, Gaussian, Blinn-Phong, Ward, Ashikhmin-Shirley), G terms
tonemap    clamp, Reinhard, ACES, exposure, sRGB
models     every registry model, and ``evaluate(name, params, l, v, n, tangent, quantity)``
"""

from oracle import fresnel, microfacet, models, tonemap, vectors

__all__ = ["fresnel", "microfacet", "models", "tonemap", "vectors"]
