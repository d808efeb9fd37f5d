// The expression language's parser: hand-written recursive descent, no Python.
//
//   expression := or
//   or         := and ("or" and)*
//   and        := not ("and" not)*
//   not        := "not" not | comparison
//   comparison := sum [("<" | "<=" | ">" | ">=" | "==" | "!=") sum]
//   sum        := product (("+" | "-") product)*
//   product    := unary (("*" | "/") unary)*
//   unary      := "-" unary | postfix
//   postfix    := primary ["@" "-" whole number]
//   primary    := number | "(" expression ")" | query | "prev(" expression ")"
//               | "last(" expression ")" | "abs(" expression ")"
//   query      := ("min" | "max" | "sum" | "mean" | "integral" | "l2" | "nonfinite"
//                 | "cells") "(" field ")"
//               | ("count" | "volume") "(" field "," number "," number ")"
//   field      := name ["[" whole number "]"]
//
// Everything is checked while parsing: a syntax error, an unknown function or
// field, a wrong number of arguments is refused with the character and what was
// expected (ExpressionError). Bounded: at most 4096 characters, nesting at most 64
// deep, at most 1000 steps back.
#pragma once

#include "Expression.h"

#include <string>
#include <vector>

namespace canopy
{

/// Parses `text`. `fields`: the field names the simulation describes; empty: any
/// name is taken (checked when the queries run). Throws ExpressionError.
Expression parseExpression(const std::string& text, const std::vector<std::string>& fields);

} // namespace canopy
