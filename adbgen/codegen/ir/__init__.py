"""The intermediate form (data only): what every pass reads and writes and every target prints.

    model          ModelIR: one model's states, parameters, programs or loop form, self-description
    loops          the loop form: Kernel and its operations (Let, Put, Balls, Columns, ...), LoopForm
    balls          BallSplit: the per-ball block (thesis Appendix A's blocks, one generic ball)
    description    SelfDescription: the self-description as the templates print it
    symbol_kinds   what a made name stands for (the name registry later passes read, not prefixes)

Nothing here transforms: the passes that make these are in `codegen.passes`.
"""
