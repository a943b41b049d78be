"""What a scene result holds, read back for comparison between runs."""

import h5py


def scene_results(path):
    """(E, sigma_y) of the calibrated layer and the impact point's (delta_max, restitution)
    of the scene result at ``path``."""
    with h5py.File(path, "r") as f:
        return (f["calibration/0"].attrs["E"], f["calibration/0"].attrs["sigma_y"],
                f["impact/point/delta_max"][()], f["impact/point/restitution"][()])
