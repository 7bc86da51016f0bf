"""The passes of code generation, in the order `regenerate.MODEL_STAGES` runs them:

    ball_split     the per-ball block from ball 1, verified against every ball (ir.balls)
    cse            the one common-subexpression pass every other pass calls
    loop_form      loop rolling: the loop form's kernels from the per-ball block (ir.loops)
    lowering       a first-order system to the intermediate form (ir.model): the loop form, or
                   straight-line programs with the structured solve (thesis Appendix A)
    description    the family's self-description resolved into data and kernels (ir.description)
    checks         verification before rendering: every program against the symbolic model, the
                   self-description, the start point
    proof          verification after rendering: every target's files compiled and run against
                   the intermediate form before anything is written

Each takes the intermediate form (or what it is made from) and returns a new one or a verdict;
none writes a file.
"""
