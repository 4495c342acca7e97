"""The model (the lowest layer): parameter sets with validation (params), the aerodynamic excitation
(excitation), the blade's Galerkin reduction (galerkin) and the contact's describing functions (contact)."""
