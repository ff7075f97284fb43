// install_compiled_ops (multibody/serial_vector_ops.h): SUNDIALS' serial vector operations,
// compiled. Reference: the library's own serial vector (N_VNew_Serial, fused operations off, as
// IDA uses it), on the same random data. The results must be equal to the last bit (tolerance
// 0), which is what keeps every IDA run's steps unchanged.
#include <multibody/serial_vector_ops.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <functional>
#include <random>
#include <vector>

using flextrack::multibody::install_compiled_ops;

namespace
{
/// Pairs of vectors with equal contents: [0] with the library's operations, [1] compiled.
class VectorPairs
{
public:
  explicit VectorPairs(const sunindextype n)
    : n(n)
  {
    SUNContext_Create(nullptr, &context);
  }
  ~VectorPairs()
  {
    for (auto &p : pairs)
      for (N_Vector v : p) N_VDestroy(v);
    SUNContext_Free(&context);
  }
  /// A new pair of random vectors (a few entries 0, 1 or -1); the compiled one is a clone of
  /// the first compiled vector, so that the clone's operations are tested too.
  std::array<N_Vector, 2> &random(std::mt19937 &rng)
  {
    std::array<N_Vector, 2> p{{N_VNew_Serial(n, context), nullptr}};
    if (pairs.empty())
      {
        p[1] = N_VNew_Serial(n, context);
        install_compiled_ops(p[1]);
      }
    else
      p[1] = N_VClone(pairs.front()[1]);
    std::uniform_real_distribution<double> u(-2, 2);
    for (sunindextype i = 0; i < n; ++i)
      {
        const double special[] = {0.0, 1.0, -1.0};
        NV_Ith_S(p[0], i) = i % 11 == 3 ? special[i % 3] : u(rng);
      }
    std::memcpy(NV_DATA_S(p[1]), NV_DATA_S(p[0]), n * sizeof(double));
    pairs.push_back(p);
    return pairs.back();
  }

private:
  sunindextype n;
  SUNContext context = nullptr;
  std::vector<std::array<N_Vector, 2>> pairs;
};

/// Bit for bit, so that a NaN (0 / 0 in "div") equals a NaN.
void expect_equal(N_Vector reference, N_Vector compiled, const std::string &what)
{
  for (sunindextype i = 0; i < NV_LENGTH_S(reference); ++i)
    ASSERT_EQ(std::memcmp(&NV_Ith_S(reference, i), &NV_Ith_S(compiled, i), sizeof(double)), 0)
      << what << ", entry " << i << ": " << NV_Ith_S(reference, i) << " against " << NV_Ith_S(compiled, i);
}

/// A mask of 1 and 0 (IDA's id vector), 1 first.
void make_mask(std::array<N_Vector, 2> &mask)
{
  for (N_Vector v : mask)
    for (sunindextype i = 0; i < NV_LENGTH_S(v); ++i) NV_Ith_S(v, i) = i % 2 == 0 ? 1.0 : 0.0;
}

const sunindextype lengths[] = {1, 37, 170};
} // namespace

TEST(SerialVectorOps, are_installed_into_serial_vectors_and_their_clones)
{
  SUNContext context;
  SUNContext_Create(nullptr, &context);
  N_Vector library = N_VNew_Serial(5, context), compiled = N_VNew_Serial(5, context);
  install_compiled_ops(compiled);
  N_Vector clone = N_VClone(compiled);
  EXPECT_NE(compiled->ops->nvlinearsum, library->ops->nvlinearsum);
  EXPECT_EQ(clone->ops->nvlinearsum, compiled->ops->nvlinearsum);
  // The fused operations stay off: their fallbacks loop over the compiled operations.
  EXPECT_EQ(compiled->ops->nvlinearcombination, nullptr);
  EXPECT_EQ(library->ops->nvlinearcombination, nullptr);
  for (N_Vector v : {library, compiled, clone}) N_VDestroy(v);
  SUNContext_Free(&context);
}

TEST(SerialVectorOps, elementwise_operations_equal_the_library_bit_for_bit)
{
  std::mt19937 rng(3);
  for (const sunindextype n : lengths)
    {
      VectorPairs v(n);
      auto z = v.random(rng);
      const double coefficients[][2] = {{1, 1},     {1, -1},   {-1, 1},  {-1, -1}, {2.5, 2.5}, {2.5, -2.5}, {0.3, 1},
                                        {1, 0.3},   {-1, 0.7}, {0.7, -1}, {0.3, 0.9}, {0, 0},    {0, 1.7},    {-0.6, 0}};
      for (const auto &[a, b] : coefficients)
        for (int alias = 0; alias < 3; ++alias) // z distinct, z = x, z = y
          {
            auto xs = v.random(rng), ys = v.random(rng);
            for (int k = 0; k < 2; ++k)
              N_VLinearSum(a, xs[k], b, ys[k], alias == 0 ? z[k] : alias == 1 ? xs[k] : ys[k]);
            const std::string what = "linear sum a = " + std::to_string(a) + ", b = " + std::to_string(b) +
                                     ", alias " + std::to_string(alias);
            expect_equal(alias == 0 ? z[0] : alias == 1 ? xs[0] : ys[0], alias == 0 ? z[1] : alias == 1 ? xs[1] : ys[1], what);
          }
      const std::vector<std::pair<std::string, std::function<void(N_Vector, N_Vector, N_Vector)>>> operations{
        {"const", [](N_Vector, N_Vector, N_Vector c) { N_VConst(-0.75, c); }},
        {"prod", [](N_Vector a, N_Vector b, N_Vector c) { N_VProd(a, b, c); }},
        {"div", [](N_Vector a, N_Vector b, N_Vector c) { N_VDiv(a, b, c); }},
        {"scale", [](N_Vector a, N_Vector, N_Vector c) { N_VScale(-1.3, a, c); }},
        {"scale by 1", [](N_Vector a, N_Vector, N_Vector c) { N_VScale(1.0, a, c); }},
        {"scale by -1", [](N_Vector a, N_Vector, N_Vector c) { N_VScale(-1.0, a, c); }},
        {"scale in place", [](N_Vector a, N_Vector, N_Vector) { N_VScale(0.7, a, a); }},
        {"abs", [](N_Vector a, N_Vector, N_Vector c) { N_VAbs(a, c); }},
        {"inv", [](N_Vector a, N_Vector, N_Vector c) { N_VInv(a, c); }},
        {"addconst", [](N_Vector a, N_Vector, N_Vector c) { N_VAddConst(a, 0.25, c); }},
        {"compare", [](N_Vector a, N_Vector, N_Vector c) { N_VCompare(1.0, a, c); }}};
      for (const auto &[name, op] : operations)
        {
          auto a = v.random(rng), b = v.random(rng), c = v.random(rng);
          for (int k = 0; k < 2; ++k) op(a[k], b[k], c[k]);
          expect_equal(c[0], c[1], name);
          expect_equal(a[0], a[1], name + " (first operand)");
        }
    }
}

TEST(SerialVectorOps, reductions_equal_the_library_bit_for_bit)
{
  std::mt19937 rng(5);
  for (const sunindextype n : lengths)
    {
      VectorPairs v(n);
      auto x = v.random(rng), w = v.random(rng), mask = v.random(rng);
      for (int k = 0; k < 2; ++k) N_VAbs(w[k], w[k]);
      make_mask(mask);
      const std::vector<std::pair<std::string, std::function<double(N_Vector, N_Vector, N_Vector)>>> reductions{
        {"dotprod", [](N_Vector a, N_Vector b, N_Vector) { return N_VDotProd(a, b); }},
        {"maxnorm", [](N_Vector a, N_Vector, N_Vector) { return N_VMaxNorm(a); }},
        {"wrmsnorm", [](N_Vector a, N_Vector b, N_Vector) { return N_VWrmsNorm(a, b); }},
        {"wrmsnormmask", [](N_Vector a, N_Vector b, N_Vector m) { return N_VWrmsNormMask(a, b, m); }},
        {"min", [](N_Vector a, N_Vector, N_Vector) { return N_VMin(a); }},
        {"wl2norm", [](N_Vector a, N_Vector b, N_Vector) { return N_VWL2Norm(a, b); }},
        {"l1norm", [](N_Vector a, N_Vector, N_Vector) { return N_VL1Norm(a); }},
        {"wsqrsumlocal", [](N_Vector a, N_Vector b, N_Vector) { return N_VWSqrSumLocal(a, b); }},
        {"wsqrsummasklocal", [](N_Vector a, N_Vector b, N_Vector m) { return N_VWSqrSumMaskLocal(a, b, m); }},
        {"dotprodlocal", [](N_Vector a, N_Vector b, N_Vector) { return N_VDotProdLocal(a, b); }},
        {"maxnormlocal", [](N_Vector a, N_Vector, N_Vector) { return N_VMaxNormLocal(a); }},
        {"minlocal", [](N_Vector a, N_Vector, N_Vector) { return N_VMinLocal(a); }},
        {"l1normlocal", [](N_Vector a, N_Vector, N_Vector) { return N_VL1NormLocal(a); }}};
      for (const auto &[name, op] : reductions)
        {
          const double reference = op(x[0], w[0], mask[0]), compiled = op(x[1], w[1], mask[1]);
          EXPECT_EQ(reference, compiled) << name << ", n = " << n;
          EXPECT_NE(reference, 0.0) << name << ": a reduction of random data is not 0";
        }
    }
}

TEST(SerialVectorOps, fused_and_array_operations_through_the_compiled_ones_equal_the_library_bit_for_bit)
{
  std::mt19937 rng(7);
  for (const sunindextype n : lengths)
    {
      VectorPairs v(n);
      const int m = 5;
      std::array<std::vector<N_Vector>, 2> X, Y, Z;
      for (int j = 0; j < m; ++j)
        for (auto *set : {&X, &Y, &Z})
          {
            auto p = v.random(rng);
            (*set)[0].push_back(p[0]), (*set)[1].push_back(p[1]);
          }
      auto x = v.random(rng), z = v.random(rng), w = v.random(rng), mask = v.random(rng);
      // Coefficients 1 and -1 take the fallback's special cases of the linear sum.
      std::vector<double> c{0.5, 1.0, -1.0, 2.25, -0.125};
      for (int count = 1; count <= m; ++count)
        for (const bool in_place : {false, true})
          {
            for (int k = 0; k < 2; ++k)
              {
                std::vector<N_Vector> terms = X[k];
                if (in_place) terms[0] = z[k]; // z = c_0 z + sum c_j X_j
                N_VLinearCombination(count, c.data(), terms.data(), z[k]);
              }
            expect_equal(z[0], z[1], "linear combination of " + std::to_string(count) + (in_place ? ", in place" : ""));
          }
      for (int k = 0; k < 2; ++k) N_VScaleAddMulti(m, c.data(), x[k], Y[k].data(), Z[k].data());
      for (int j = 0; j < m; ++j) expect_equal(Z[0][j], Z[1][j], "scale add multi");
      std::array<std::vector<double>, 2> d{{std::vector<double>(m), std::vector<double>(m)}};
      for (int k = 0; k < 2; ++k) N_VDotProdMulti(m, x[k], Y[k].data(), d[k].data());
      EXPECT_EQ(d[0], d[1]) << "dot product multi";
      for (const auto &[a, b] : {std::pair{1.0, -1.0}, {0.5, 0.5}, {0.3, 1.7}})
        {
          for (int k = 0; k < 2; ++k) N_VLinearSumVectorArray(m, a, X[k].data(), b, Y[k].data(), Z[k].data());
          for (int j = 0; j < m; ++j) expect_equal(Z[0][j], Z[1][j], "linear sum vector array");
        }
      for (int k = 0; k < 2; ++k) N_VScaleVectorArray(m, c.data(), X[k].data(), Z[k].data());
      for (int j = 0; j < m; ++j) expect_equal(Z[0][j], Z[1][j], "scale vector array");
      for (int k = 0; k < 2; ++k) N_VConstVectorArray(m, 3.5, Z[k].data());
      for (int j = 0; j < m; ++j) expect_equal(Z[0][j], Z[1][j], "const vector array");
      for (int k = 0; k < 2; ++k) N_VAbs(w[k], w[k]);
      make_mask(mask);
      std::vector<N_Vector> W0(m, w[0]), W1(m, w[1]);
      for (int k = 0; k < 2; ++k) N_VWrmsNormVectorArray(m, X[k].data(), (k ? W1 : W0).data(), d[k].data());
      EXPECT_EQ(d[0], d[1]) << "wrms norm vector array";
      for (int k = 0; k < 2; ++k)
        N_VWrmsNormMaskVectorArray(m, X[k].data(), (k ? W1 : W0).data(), mask[k], d[k].data());
      EXPECT_EQ(d[0], d[1]) << "wrms norm mask vector array";
    }
}
