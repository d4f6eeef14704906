//! Homogenisation (seed chapter 5.1): tangent-modulus law, hyperfoam and Prony fits, material cards.
