"""The parametric dolphin model: procedural template builder, template asset, M(β, θ, P)."""
