"""The FMUs' parameters as typed records, one module per model, generated from the models' variable
specs (fmu_src/models/<Model>/model.toml) by fmu_src/gen: frozen dataclasses with the start values
as defaults and the unit, bounds, value reference and description of every field in its metadata."""
