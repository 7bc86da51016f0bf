"""The two-plane rigid rotor with an automatic ball balancer (Rodrigues et al. 2011).

scene -> symbols -> model (Lagrange, paper (2)-(4)) -> reductions ((7)-(8), first-order form, (40),
single-plane limit) -> critical_speeds ((11), (32)), symmetry ((13)-(16)), normal_form ((17)-(39)),
branches (the full model's B and C3), jacobi, transient (run-ups), verify (every check).
"""
