"""What runs a task: secrets and attempts, the metered and served development environments (``devenv``,
``devservice``), sandboxed policies (``policy``, ``onnx_policy``) and the parallel runner (``runner``)."""
