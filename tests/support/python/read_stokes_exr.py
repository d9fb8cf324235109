"""Reads a spar Stokes EXR with the two readers the field uses and prints
what they found as JSON on stdout (tests/cli/cli_stokes_exr.rs compares it
with spar's own values):

- colour-science's reader of the JCGT 2021 spectral layout
  (colour.read_spectral_image_Fichet2021, which parses the channel names
  itself and reads the pixels through OpenImageIO);
- OpenImageIO's Python module, each channel looked up by its name.

usage: python read_stokes_exr.py FILE CHANNEL... (the channels for the
OpenImageIO look-up). Exits non-zero with a message if a reader fails.
"""

import json
import sys
import warnings

warnings.simplefilter("ignore")  # colour warns about optional packages

import colour  # noqa: E402
import numpy as np  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

path, names = sys.argv[1], sys.argv[2:]
components, spec = colour.read_spectral_image_Fichet2021(path, additional_data=True)
out = {
    "colour_version": colour.__version__,
    "is_emissive": bool(spec.is_emissive),
    "is_polarised": bool(spec.is_polarised),
    "attributes": {a.name: str(a.value) for a in spec.attributes},
    # component -> [wavelengths (nm)], [[row-major pixel values per wavelength]]
    "components": {
        str(k): {
            "wavelengths": [float(w) for w in v[0]],
            "values": np.asarray(v[1], dtype=np.float64).reshape(-1, len(v[0])).T.tolist(),
        }
        for k, v in components.items()
    },
}
inp = oiio.ImageInput.open(path)
if inp is None:
    sys.exit(f"OpenImageIO cannot open {path}: {oiio.geterror()}")
s = inp.spec()
pixels = inp.read_image(0, 0, 0, s.nchannels, "float")
inp.close()
by_name = {}
for n in names:
    i = s.channelindex(n)
    if i < 0:
        sys.exit(f"OpenImageIO: no channel {n!r} in {path} (it has {list(s.channelnames)})")
    by_name[n] = np.asarray(pixels[:, :, i], dtype=np.float64).ravel().tolist()
out["oiio"] = by_name
out["oiio_attributes"] = {
    k: s.get_string_attribute(k)
    for k in ("spectralLayoutVersion", "emissiveUnits", "polarisationHandedness")
}
json.dump(out, sys.stdout)
