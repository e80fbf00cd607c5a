"""The kitchen agent harness: public modules laid into the agent's workspace as ``harness/``.

Level 1 gets ``robot`` (the 12-D action and the metered client); level 2 adds ``geometry`` (camera
geometry, frame transforms, point clouds), ``perception`` (segmentation in SAM3's schema, grasp
proposals in Contact-GraspNet's) and ``motion`` (closed-loop motion primitives); level 3 adds
``world`` (world-frame object and fixture poses, the target and the grasp state). The modules import
only ``numpy`` and ``rle_design``.
"""
