"""Commands that prepare inputs: tiles to one map (stitch), any format to X3P (convert), synthetic
surfaces (synth), DMA sweeps to a master curve (rubber). One module per command, as in
``commands/``."""
