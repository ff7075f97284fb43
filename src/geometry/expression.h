// A small algebraic expression in one variable, evaluated on Taylor jets.
//
// Why not deal.II's FunctionParser: muParser evaluates values only, and curvature, torsion and
// their derivatives need exact first to fourth derivatives of the curve. This parser accepts
// the muParser syntax users already know (+ - * / ^, parentheses, sin cos tan exp log sqrt
// sinh cosh tanh atan abs, the constant pi, and named user constants) and evaluates on jets.
#pragma once

#include <geometry/taylor.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace flextrack::geometry
{
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

  double value(const double x) const { return evaluate(Jet::constant(x)).value(); }
  /// Value and first four derivatives at x.
  Jet jet(const double x) const { return evaluate(Jet::variable(x)); }
  const std::string &text() const { return source; }

private:
  enum class Op { constant, variable, add, sub, mul, div, pow, neg, func };
  struct Node
  {
    Op op;
    double value = 0;   // for constants
    int a = -1, b = -1; // operand node indices
    std::string function;
  };

  Jet evaluate(const Jet &x) const;
  Jet evaluate_node(int index, const Jet &x) const;

  // Recursive-descent parser over `source`, position `pos`.
  int parse_sum();
  int parse_product();
  int parse_unary();
  int parse_power();
  int parse_primary();
  void skip_blanks();
  [[noreturn]] void fail(const std::string &what) const;
  int add(Node n) { nodes.push_back(std::move(n)); return static_cast<int>(nodes.size()) - 1; }

  std::string source, variable_name;
  std::map<std::string, double> constant_values;
  std::vector<Node> nodes;
  int root = -1;
  std::size_t pos = 0;
};

/// Parse "a=1.5, b = 2" into a name -> value map (throws ExpressionError).
std::map<std::string, double> parse_constants(const std::string &text);
} // namespace flextrack::geometry
