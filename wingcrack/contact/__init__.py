"""Fracture contact: constraint rows on matched face-node pairs and the
primal-dual active-set solution of the KKT conditions (paper section 2.1, 3.1)."""
