"""RLE-Bench tasks: the 51 task instances of the paper, their verifiers and the shared runtime."""

import rle_design  # noqa: E402,F401  (sets the BLAS kernel family and GL backend before numpy loads)

# A process that verifies or builds several tasks compiles more meshes than MuJoCo's default cache keeps.
rle_design.widen_mujoco_asset_cache()
