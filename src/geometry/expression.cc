#include <geometry/expression.h>
#include <base/text.h>

#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace flextrack::geometry
{
namespace
{
struct KnownFunction
{
  int arguments;
  int id; ///< Expression::Function, as a number (the enum is private to Expression)
};
/// Every function with its number of arguments, in the order of Expression::Function (from 1).
const std::map<std::string, KnownFunction> known_functions = {
  {"sin", {1, 1}},   {"cos", {1, 2}},  {"tan", {1, 3}},  {"sinh", {1, 4}}, {"cosh", {1, 5}},  {"tanh", {1, 6}},
  {"exp", {1, 7}},   {"log", {1, 8}},  {"sqrt", {1, 9}}, {"atan", {1, 10}}, {"abs", {1, 11}}, {"min", {2, 12}},
  {"max", {2, 13}},  {"if", {3, 14}},  {"step", {1, 15}}, {"smoothstep", {1, 16}}};
std::string function_list()
{
  std::string s;
  for (const auto &[f, n] : known_functions) s += (s.empty() ? "" : " ") + f;
  return s;
}
} // namespace

Expression::Expression(const std::string &text, const std::string &variable,
                       const std::map<std::string, double> &constants)
  : source(text), variable_name(variable), constant_values(constants)
{
  if (source.size() > max_expression_length)
    throw ExpressionError("the expression \"" + base::printable_excerpt(source, 40) + "\" has " +
                          std::to_string(source.size()) + " characters; at most " +
                          std::to_string(max_expression_length) + " are allowed");
  constant_values.emplace("pi", M_PI);
  skip_blanks();
  if (pos == source.size())
    fail("an expression, but the text is empty");
  root = parse_comparison();
  skip_blanks();
  if (pos != source.size())
    fail("an operator (+ - * / ^ < > <= >=) or the end of the expression");
}

Expression::Level::Level(Expression &e) : expression(e)
{
  if (++expression.depth > max_expression_depth)
    expression.fail_because("nested deeper than " + std::to_string(max_expression_depth) +
                            " levels (each parenthesis, function argument, sign and exponent opens one); at most " +
                            std::to_string(max_expression_depth) + " are allowed: simplify the expression or move "
                            "parts of it into Constants");
}

void Expression::fail_because(const std::string &reason) const
{
  // Quote a short printable excerpt around the position, never the whole (possibly huge) text.
  constexpr std::size_t before = 30, width = 60;
  const std::size_t start = pos > before ? pos - before : 0;
  std::ostringstream m;
  m << "cannot parse expression \"" << (start > 0 ? "..." : "")
    << base::printable_excerpt(source.substr(start), width) << "\" at character " << pos + 1 << ": " << reason;
  throw ExpressionError(m.str());
}

void Expression::skip_blanks()
{
  while (pos < source.size() && std::isspace(static_cast<unsigned char>(source[pos]))) ++pos;
}

int Expression::parse_comparison()
{
  const int left = parse_sum();
  skip_blanks();
  if (pos >= source.size() || (source[pos] != '<' && source[pos] != '>')) return left;
  const bool less = source[pos++] == '<';
  const bool or_equal = pos < source.size() && source[pos] == '=';
  if (or_equal) ++pos;
  const int right = parse_sum();
  const Op op = less ? (or_equal ? Op::less_equal : Op::less) : (or_equal ? Op::greater_equal : Op::greater);
  return add({op, 0, left, right, {}});
}

int Expression::parse_sum()
{
  int left = parse_product();
  for (;;)
    {
      skip_blanks();
      if (pos < source.size() && (source[pos] == '+' || source[pos] == '-'))
        {
          const Op op = source[pos++] == '+' ? Op::add : Op::sub;
          const int right = parse_product();
          left = add({op, 0, left, right, {}});
        }
      else
        return left;
    }
}

int Expression::parse_product()
{
  int left = parse_unary();
  for (;;)
    {
      skip_blanks();
      if (pos < source.size() && (source[pos] == '*' || source[pos] == '/'))
        {
          const Op op = source[pos++] == '*' ? Op::mul : Op::div;
          const int right = parse_unary();
          left = add({op, 0, left, right, {}});
        }
      else
        return left;
    }
}

int Expression::parse_unary()
{
  skip_blanks();
  if (pos < source.size() && (source[pos] == '-' || source[pos] == '+'))
    {
      const bool negate = source[pos++] == '-';
      const Level level(*this);
      const int operand = parse_unary();
      return negate ? add({Op::neg, 0, operand, -1, {}}) : operand;
    }
  return parse_power();
}

int Expression::parse_power()
{
  const int base = parse_primary();
  skip_blanks();
  if (pos < source.size() && source[pos] == '^')
    {
      ++pos;
      const Level level(*this);
      const int exponent = parse_unary(); // right associative: a^b^c = a^(b^c)
      return add({Op::pow, 0, base, exponent, {}});
    }
  return base;
}

int Expression::parse_primary()
{
  skip_blanks();
  if (pos >= source.size())
    fail("a number, a name or '('");
  const char c = source[pos];
  if (c == '(')
    {
      ++pos;
      const Level level(*this);
      const int inner = parse_comparison();
      skip_blanks();
      if (pos >= source.size() || source[pos] != ')')
        fail("')'");
      ++pos;
      return inner;
    }
  if (std::isdigit(static_cast<unsigned char>(c)) || c == '.')
    {
      const char *begin = source.c_str() + pos;
      char *end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin)
        fail("a number");
      if (!std::isfinite(v))
        fail("a finite number (at most about 1.8e308)");
      pos += static_cast<std::size_t>(end - begin);
      return add({Op::constant, v, -1, -1, {}});
    }
  if (std::isalpha(static_cast<unsigned char>(c)) || c == '_')
    {
      const std::size_t start = pos;
      while (pos < source.size() &&
             (std::isalnum(static_cast<unsigned char>(source[pos])) || source[pos] == '_'))
        ++pos;
      const std::string name = source.substr(start, pos - start);
      skip_blanks();
      if (pos < source.size() && source[pos] == '(')
        {
          const auto known = known_functions.find(name);
          if (known == known_functions.end())
            {
              pos = start;
              fail("a known function (" + function_list() + "), not \"" + base::printable_excerpt(name, 40) + "\"");
            }
          ++pos;
          const Level level(*this);
          int arguments[3] = {-1, -1, -1};
          for (int k = 0; k < known->second.arguments; ++k)
            {
              if (k > 0)
                {
                  skip_blanks();
                  if (pos >= source.size() || source[pos] != ',')
                    fail("',' and argument " + std::to_string(k + 1) + " of " + name + " (it takes " +
                         std::to_string(known->second.arguments) + ")");
                  ++pos;
                }
              arguments[k] = parse_comparison();
            }
          skip_blanks();
          if (pos >= source.size() || source[pos] != ')')
            fail("')' after the " + std::string(known->second.arguments == 1 ? "argument" : "arguments") + " of " + name +
                 " (it takes " + std::to_string(known->second.arguments) + ")");
          ++pos;
          Node call{Op::func, 0, arguments[0], arguments[1], static_cast<Function>(known->second.id)};
          call.c = arguments[2];
          return add(call);
        }
      if (name == variable_name)
        return add({Op::variable, 0, -1, -1, {}});
      if (const auto it = constant_values.find(name); it != constant_values.end())
        return add({Op::constant, it->second, -1, -1, {}});
      pos = start;
      fail("the variable \"" + variable_name + "\", pi or a declared constant, not the unknown name \"" +
           base::printable_excerpt(name, 40) + "\"");
    }
  fail("a number, a name or '(' (found '" + base::printable_excerpt(std::string(1, c)) + "')");
}

template <int N>
TaylorJet<N> Expression::evaluate(const TaylorJet<N> &x) const
{
  // Operands precede their operation in `nodes` (a node is added after its operands are
  // parsed), so one pass in index order evaluates the tree without recursion.
  constexpr std::size_t on_stack = 32;
  std::array<TaylorJet<N>, on_stack> small;
  std::vector<TaylorJet<N>> large;
  TaylorJet<N> *values = small.data();
  if (nodes.size() > on_stack)
    {
      large.resize(nodes.size());
      values = large.data();
    }
  for (int i = 0; i <= root; ++i) values[i] = evaluate_node(nodes[i], values, x);
  return values[root];
}

template <int N>
TaylorJet<N> Expression::evaluate_node(const Node &n, const TaylorJet<N> *values, const TaylorJet<N> &x) const
{
  switch (n.op)
    {
      case Op::constant: return TaylorJet<N>::constant(n.value);
      case Op::variable: return x;
      case Op::add: return values[n.a] + values[n.b];
      case Op::sub: return values[n.a] - values[n.b];
      case Op::mul: return values[n.a] * values[n.b];
      case Op::div: return values[n.a] / values[n.b];
      case Op::neg: return -values[n.a];
      case Op::less: return TaylorJet<N>::constant(values[n.a].c[0] < values[n.b].c[0] ? 1 : 0);
      case Op::greater: return TaylorJet<N>::constant(values[n.a].c[0] > values[n.b].c[0] ? 1 : 0);
      case Op::less_equal: return TaylorJet<N>::constant(values[n.a].c[0] <= values[n.b].c[0] ? 1 : 0);
      case Op::greater_equal: return TaylorJet<N>::constant(values[n.a].c[0] >= values[n.b].c[0] ? 1 : 0);
      case Op::pow:
        {
          // A constant exponent (no variable in its subtree, decided when parsed, so that jets of
          // every order and plain values take the same route): the power rule, valid for negative
          // bases too; otherwise exp(exponent log(base)).
          const TaylorJet<N> &base = values[n.a], &exponent = values[n.b];
          return nodes[n.b].has_variable ? exp(exponent * log(base)) : pow(base, exponent.c[0]);
        }
      case Op::func:
        {
          const TaylorJet<N> &a = values[n.a];
          TaylorJet<N> s, c;
          switch (n.function)
            {
              case Function::sin: sin_cos(a, s, c); return s;
              case Function::cos: sin_cos(a, s, c); return c;
              case Function::tan: sin_cos(a, s, c); return s / c;
              case Function::sinh: sin_cos(a, s, c, true); return s;
              case Function::cosh: sin_cos(a, s, c, true); return c;
              case Function::tanh: sin_cos(a, s, c, true); return s / c;
              case Function::exp: return exp(a);
              case Function::log: return log(a);
              case Function::sqrt: return sqrt(a);
              case Function::atan: return atan(a);
              case Function::abs: return a.c[0] < 0 ? -a : a;
              case Function::min: return values[n.b].c[0] < a.c[0] ? values[n.b] : a;
              case Function::max: return values[n.b].c[0] > a.c[0] ? values[n.b] : a;
              case Function::if_: return a.c[0] != 0 ? values[n.b] : values[n.c];
              case Function::step: return TaylorJet<N>::constant(a.c[0] >= 0 ? 1 : 0);
              case Function::smoothstep:
                {
                  if (a.c[0] <= 0) return TaylorJet<N>::constant(0);
                  if (a.c[0] >= 1) return TaylorJet<N>::constant(1);
                  // 10 a^3 - 15 a^4 + 6 a^5 = a^3 (10 + a (-15 + 6 a))
                  const TaylorJet<N> inner = TaylorJet<N>::constant(10) + a * (TaylorJet<N>::constant(-15) + 6.0 * a);
                  return a * a * a * inner;
                }
              case Function::none: break;
            }
        }
    }
  return TaylorJet<N>(); // unreachable: the parser only creates known nodes
}

template Jet Expression::evaluate(const Jet &) const;
template Dual Expression::evaluate(const Dual &) const;

std::map<std::string, double> parse_constants(const std::string &text)
{
  std::map<std::string, double> result;
  std::istringstream in(text);
  std::string item;
  std::size_t count = 0;
  while (std::getline(in, item, ','))
    {
      const auto eq = item.find('=');
      using base::trim;
      if (trim(item).empty()) continue;
      if (++count > max_constants)
        throw ExpressionError("more than " + std::to_string(max_constants) + " constants; at most " +
                              std::to_string(max_constants) + " are allowed");
      if (eq == std::string::npos)
        throw ExpressionError("constant definition \"" + base::printable_excerpt(trim(item), 40) +
                              "\" is not of the form name=value");
      const std::string name = trim(item.substr(0, eq));
      // A constant's value may use the constants defined before it.
      const Expression value(trim(item.substr(eq + 1)), "", result);
      if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_'))
        throw ExpressionError("constant name \"" + base::printable_excerpt(name, 40) + "\" must start with a letter");
      const double v = value.value(0.0);
      if (!std::isfinite(v))
        throw ExpressionError("constant \"" + base::printable_excerpt(name, 40) + "\" is not finite (" +
                              base::printable_excerpt(value.text(), 40) + "); allowed: finite values");
      result[name] = v;
    }
  return result;
}
} // namespace flextrack::geometry
