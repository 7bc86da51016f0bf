"""Code generation: intermediate form (`ir`), printers, rendering through templates, the default set."""
