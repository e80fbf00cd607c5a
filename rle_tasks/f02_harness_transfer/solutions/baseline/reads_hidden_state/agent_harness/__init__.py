"""A harness that reads the verifier's state outside its own directory."""
