"""The Harbor export: task directories (``export``), their images (``images``) and README (``readme``),
the development sidecar (``sidecar``), the verifier's reward (``reward``), and results back from Harbor
job directories (``results``)."""
