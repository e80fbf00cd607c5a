"""Public modules of family 04, laid into the agent's workspace: the G1 model and its PD constants,
the 50 Hz clip format, the tracking environment, PPO and the ONNX exporter. They import only
``rle_design``, numpy, MuJoCo and (PPO, exporter) torch."""
