"""Reads a reduced body file with h5py by the names documented in doc/reduced_body_file.md and
checks shapes and the mass-orthonormal basis; reads the exported VTU with meshio and checks that a
nodal value equals the HDF5 one to 1e-12 (issue 5). Usage: check_reduced_body.py BODY.h5 MODES.vtu"""
import sys

import h5py
import meshio
import numpy as np

body, vtu = sys.argv[1], sys.argv[2]
with h5py.File(body, "r") as f:
    assert f.attrs["format"] == b"FlexTrack reduced body", f.attrs["format"]
    assert int(f.attrs["format_version"]) == 4
    # Version 3: a content checksum (its definition is checked in tests/badinput/hostile_reduced_body.py).
    checksum = f.attrs["content_checksum"].decode()
    assert len(checksum) == 16 and int(checksum, 16) >= 0, checksum
    n = int(f.attrs["n_modes"])
    K, M, C = f["reduced/stiffness"][...], f["reduced/mass"][...], f["reduced/damping"][...]
    freq = f["reduced/frequencies_hz"][...]
    assert K.shape == M.shape == C.shape == (n, n) and freq.shape == (n,)
    # Mass-normalised, K diagonal: Phi^T M Phi = 1 to round-off; frequencies from K.
    assert np.abs(M - np.eye(n)).max() < 1e-10, np.abs(M - np.eye(n)).max()
    assert np.allclose(np.sqrt(np.diag(K)) / (2 * np.pi), freq, rtol=1e-10)
    m = f["inertia/mass"][0]
    s = f["inertia/first_moment"][...]
    J = f["inertia/inertia_origin"][...]
    assert m > 0 and s.shape == (3,) and J.shape == (3, 3)
    assert f["inertia/I3"].shape == (3, n) and f["inertia/I4"].shape == (3, n)
    assert f["inertia/P"].shape == (n, 3, 3) and f["inertia/Q"].shape == (n, n, 3, 3)
    for name in f["interfaces"]:
        g = f["interfaces"][name]
        assert g["position"].shape == (3,) and g["modes"].shape == (6, n)
    for name in f["arms"]:
        g = f["arms"][name]
        cells = g["cell_arc_length"].shape[0] - 1
        p1 = g["reference_nodes"].shape[0]
        assert g["modes"].shape == (cells * p1, n, 6) and g["positions"].shape == (cells * p1, 3)
    points = f["drawing/points"][...]
    modes = f["drawing/mode_displacements"][...]
    assert modes.shape == (n, points.shape[0], 3)
    print(f"h5py: {n} modes, mass {m:.6g} kg, centre {s / m}, interfaces {list(f['interfaces'])}, arms {list(f['arms'])}")

mesh = meshio.read(vtu)
assert np.abs(mesh.points - points).max() == 0.0
k, i = min(4, n - 1), points.shape[0] // 3
value = mesh.point_data[f"mode_{k + 1:03d}"][i]
error = np.abs(value - modes[k, i]).max() / np.abs(modes[k]).max()
print(f"meshio: mode_{k + 1:03d} at point {i} = {value}, HDF5 {modes[k, i]}, relative difference {error:.1e}")
assert error < 1e-12
# For the ParaView check: the point, the array and the expected value.
print(f"CHECK {k + 1:03d} {i} {modes[k, i, 0]!r} {modes[k, i, 1]!r} {modes[k, i, 2]!r}")
