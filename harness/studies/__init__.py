"""The studies (layer above system): the paper's studies, the claims table and the figures; the
mistuning study of the ring."""
