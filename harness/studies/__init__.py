"""The paper's studies, the claims table and the figures."""
