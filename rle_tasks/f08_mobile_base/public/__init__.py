"""Public modules of 08-mobile-base, laid into the agent workspace as the package ``mobile_base``:
the evaluator's scene (wheel drive, arm, payload, shelf) and the preview. They import only
``rle_design`` and each other (relative imports), so they run the same in the workspace and here."""
