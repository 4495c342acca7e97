"""The FMU against the independent reference: the drivers that run both and compare.

`validate` (the `validate` command's cases), `hysteresis` (Fig. 2: the FMU's friction loop against
the reference's), `reproduction` (the paper's studies with Fig. 2), `ring_states` (which steady state
a tuned ring settles on, co-simulation against the monolithic reference) and `ring_convergence`
(the ring's co-simulation error as the communication step shrinks). This layer sits above
`harness.studies` and below `harness.cli`; it imports the product and `harness.reference`, and no
product module imports it (docs/layers.md).
"""
