// A small algebraic expression in one variable, evaluated on Taylor jets.
//
// Why not deal.II's FunctionParser: muParser evaluates values only, and curvature, torsion and
// their derivatives need exact first to fourth derivatives of the curve. This parser accepts
// the muParser syntax users already know (+ - * / ^, parentheses, sin cos tan exp log sqrt
// sinh cosh tanh atan abs, the constant pi, and named user constants) and evaluates on jets.
// For laws of time that switch (a ramp and hold, a drive that starts at t0): the comparisons
// < > <= >= (1 if true, else 0), min(a, b), max(a, b), if(c, a, b) (a where c is not 0, else b),
// step(x) (0 for x < 0, 1 from x = 0 on) and smoothstep(x) (0 for x <= 0, 1 for x >= 1, and
// 6x^5 - 15x^4 + 10x^3 between: value, slope and curvature continuous, so a drive built on it
// has a continuous acceleration).
//
// Limits (a scene may come from someone else, and a parser must not crash on it):
//  - an expression holds at most max_expression_length = 10000 characters;
//  - it nests at most max_expression_depth = 200 levels, where each parenthesis, function
//    argument, sign ('-' or '+' before an operand) and exponent ('^') opens one level: the
//    parser is recursive, and 100000 nested parentheses would exhaust the stack;
//  - numbers and constants are finite, at most max_constants constants per definition list.
// Evaluation does not recurse at all: the node list is in post-order (operands before the
// operation), so one pass in index order evaluates any tree, e.g. the left-leaning tree of a
// long sum, in constant stack depth.
#pragma once

#include <geometry/taylor.h>

#include <cstddef>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace flextrack::geometry
{
constexpr std::size_t max_expression_length = 10000;
constexpr int max_expression_depth = 200;
constexpr std::size_t max_constants = 1000;

/// Thrown for text that does not parse; what() says where and what was expected.
class ExpressionError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

class Expression
{
public:
  /// Parse @p text; @p variable is the name of the independent variable ("t" or "s"),
  /// @p constants are further names with fixed values.
  Expression(const std::string &text, const std::string &variable,
             const std::map<std::string, double> &constants = {});

  double value(const double x) const { return evaluate(Dual::constant(x)).value(); }
  /// Value and first four derivatives at x.
  Jet jet(const double x) const { return evaluate(Jet::variable(x)); }
  /// Value and first derivative at x: bit for bit the first two coefficients of jet(x), at a
  /// fraction of its cost (taylor.h).
  Dual dual(const double x) const { return evaluate(Dual::variable(x)); }
  const std::string &text() const { return source; }

private:
  enum class Op { constant, variable, add, sub, mul, div, pow, neg, func, less, greater, less_equal, greater_equal };
  /// The functions, resolved from their names once, when parsed.
  enum class Function { none, sin, cos, tan, sinh, cosh, tanh, exp, log, sqrt, atan, abs, min, max, if_, step, smoothstep };
  struct Node
  {
    Op op;
    double value = 0;   // for constants
    int a = -1, b = -1; // operand node indices
    Function function = Function::none;
    int c = -1;         // third operand (if)
    bool has_variable = false; ///< the node's subtree holds the variable (set by add())
  };

  template <int N>
  TaylorJet<N> evaluate(const TaylorJet<N> &x) const;
  /// Node @p n given the values of all nodes before it (its operands among them).
  template <int N>
  TaylorJet<N> evaluate_node(const Node &n, const TaylorJet<N> *values, const TaylorJet<N> &x) const;

  // Recursive-descent parser over `source`, position `pos`.
  int parse_comparison();
  int parse_sum();
  int parse_product();
  int parse_unary();
  int parse_power();
  int parse_primary();
  void skip_blanks();
  /// One more nesting level for the lifetime of the guard; fails beyond max_expression_depth.
  struct Level
  {
    explicit Level(Expression &e);
    ~Level() { --expression.depth; }
    Level(const Level &) = delete;
    Level &operator=(const Level &) = delete;
    Expression &expression;
  };
  /// ExpressionError "cannot parse expression "...": at character N: expected @p what".
  [[noreturn]] void fail(const std::string &what) const { fail_because("expected " + what); }
  [[noreturn]] void fail_because(const std::string &reason) const;
  int add(Node n)
  {
    n.has_variable = n.op == Op::variable;
    for (const int operand : {n.a, n.b, n.c})
      if (operand >= 0) n.has_variable = n.has_variable || nodes[operand].has_variable;
    nodes.push_back(std::move(n));
    return static_cast<int>(nodes.size()) - 1;
  }

  std::string source, variable_name;
  std::map<std::string, double> constant_values;
  std::vector<Node> nodes;
  int root = -1;
  std::size_t pos = 0;
  int depth = 0; ///< nesting level while parsing
};

/// Parse "a=1.5, b = 2" into a name -> value map (throws ExpressionError): at most
/// max_constants constants, each finite.
std::map<std::string, double> parse_constants(const std::string &text);
} // namespace flextrack::geometry
