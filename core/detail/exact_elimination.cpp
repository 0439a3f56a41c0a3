#include "core/detail/exact_elimination.h"

#include <gmpxx.h>

#include <algorithm>
#include <map>
#include <utility>

namespace bary::detail
{

namespace
{

mpq_class twice_area(const std::array<double, 2>& a, const std::array<double, 2>& b,
  const std::array<double, 2>& c)
{
  // Every double is an exact rational (mpq_class(double) does not round).
  const mpq_class ax(a[0]), ay(a[1]), bx(b[0]), by(b[1]), cx(c[0]), cy(c[1]);
  return (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
}

std::array<mpq_class, 3> barycentric(const std::array<std::array<double, 2>, 4>& v)
{
  const mpq_class A = twice_area(v[0], v[1], v[2]);
  return { twice_area(v[3], v[1], v[2]) / A, twice_area(v[0], v[3], v[2]) / A,
    twice_area(v[0], v[1], v[3]) / A };
}

/// A row with integer coefficients, sorted by column (a rational row times a positive number:
/// the same linear relation).
using Row = std::vector<std::pair<int, mpz_class>>;

/// The condition's coefficients (-1, beta0, beta1, beta2) times their common denominator.
std::array<mpz_class, 4> integer_coefficients(const std::array<std::array<double, 2>, 4>& v)
{
  const auto b = barycentric(v);
  mpz_class den = 1;
  for (const auto& q : b)
    den = lcm(den, mpz_class(q.get_den()));
  std::array<mpz_class, 4> out;
  out[0] = -den;
  for (int k = 0; k < 3; ++k)
    out[static_cast<size_t>(k) + 1] = b[static_cast<size_t>(k)].get_num() * (den / b[static_cast<size_t>(k)].get_den());
  return out;
}

/// Divides the row by the gcd of its entries.
void remove_content(Row& row)
{
  mpz_class g = 0;
  for (const auto& e : row)
  {
    g = gcd(g, e.second);
    if (g == 1)
      return;
  }
  if (g > 1)
    for (auto& e : row)
      mpz_divexact(e.second.get_mpz_t(), e.second.get_mpz_t(), g.get_mpz_t());
}

/// row := a row - b pivot (sparse merge), zeros dropped.
Row combine(const Row& row, const mpz_class& a, const Row& pivot, const mpz_class& b)
{
  Row out;
  out.reserve(row.size() + pivot.size());
  size_t i = 0, j = 0;
  while (i < row.size() || j < pivot.size())
  {
    if (j >= pivot.size() || (i < row.size() && row[i].first < pivot[j].first))
    {
      out.emplace_back(row[i].first, a * row[i].second);
      ++i;
    }
    else if (i >= row.size() || pivot[j].first < row[i].first)
    {
      out.emplace_back(pivot[j].first, -b * pivot[j].second);
      ++j;
    }
    else
    {
      mpz_class v = a * row[i].second - b * pivot[j].second;
      if (sgn(v) != 0)
        out.emplace_back(row[i].first, std::move(v));
      ++i;
      ++j;
    }
  }
  return out;
}

} // namespace

std::array<double, 3> exact_barycentric(const std::array<std::array<double, 2>, 4>& vertex)
{
  const auto b = barycentric(vertex);
  return { b[0].get_d(), b[1].get_d(), b[2].get_d() };
}

// Fraction-free elimination on sparse integer rows. Each new row is reduced by the kept rows
// whose pivot columns it has (the earliest first: a kept row holds no pivot column of an earlier
// one, so this ends); its pivot is the unknown column that the fewest rows still to come
// contain (none, for most conditions: a row point seen by no other condition), which keeps the
// rows short. The conditions of one edge share their betas, computed once.
ExactElimination eliminate_exact(
  const std::vector<ExactCondition>& rows, int unknowns, int anchors)
{
  ExactElimination out;
  const int ncols = unknowns + anchors;
  std::vector<int> remaining(static_cast<size_t>(ncols), 0);
  for (const auto& row : rows)
    for (int c : row.column)
      if (c >= 0 && c < unknowns)
        ++remaining[static_cast<size_t>(c)];
  std::map<std::array<double, 8>, std::array<mpz_class, 4>> coefficient_cache;
  std::vector<Row> pivot_rows;
  std::vector<int> pivot_of(static_cast<size_t>(ncols), -1);
  std::vector<int> pivot_col;
  for (size_t r = 0; r < rows.size(); ++r)
  {
    const ExactCondition& in = rows[r];
    for (int c : in.column)
      if (c >= 0 && c < unknowns)
        --remaining[static_cast<size_t>(c)];
    std::array<double, 8> key;
    for (int k = 0; k < 4; ++k)
    {
      key[static_cast<size_t>(2 * k)] = in.vertex[static_cast<size_t>(k)][0];
      key[static_cast<size_t>(2 * k + 1)] = in.vertex[static_cast<size_t>(k)][1];
    }
    auto it = coefficient_cache.find(key);
    if (it == coefficient_cache.end())
      it = coefficient_cache.emplace(key, integer_coefficients(in.vertex)).first;
    Row row;
    for (int k = 0; k < 4; ++k)
    {
      const int c = in.column[static_cast<size_t>(k)];
      if (c < 0)
        continue;
      auto pos = std::find_if(row.begin(), row.end(), [&](const auto& e) { return e.first == c; });
      if (pos == row.end())
        row.emplace_back(c, it->second[static_cast<size_t>(k)]);
      else
        pos->second += it->second[static_cast<size_t>(k)];
    }
    row.erase(std::remove_if(row.begin(), row.end(), [](const auto& e) { return sgn(e.second) == 0; }),
      row.end());
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (row.empty())
      continue; // only fixed points: a relation the current spline satisfies
    for (;;)
    {
      int k = -1;
      mpz_class coeff;
      for (const auto& e : row)
        if (e.first < unknowns)
        {
          const int p = pivot_of[static_cast<size_t>(e.first)];
          if (p >= 0 && (k < 0 || p < k))
          {
            k = p;
            coeff = e.second;
          }
        }
      if (k < 0)
        break;
      const Row& piv = pivot_rows[static_cast<size_t>(k)];
      const int pc = pivot_col[static_cast<size_t>(k)];
      const auto pe = std::lower_bound(piv.begin(), piv.end(), pc,
        [](const auto& e, int c) { return e.first < c; });
      const mpz_class a = pe->second;
      const mpz_class g = gcd(a, coeff);
      row = combine(row, a / g, piv, coeff / g);
      remove_content(row);
    }
    int lead = -1;
    for (const auto& e : row)
      if (e.first < unknowns &&
        (lead < 0 || remaining[static_cast<size_t>(e.first)] < remaining[static_cast<size_t>(lead)]))
        lead = e.first;
    if (lead < 0)
    {
      if (out.conflict < 0 && !row.empty())
        out.conflict = static_cast<int>(r);
      continue;
    }
    pivot_of[static_cast<size_t>(lead)] = static_cast<int>(pivot_rows.size());
    pivot_rows.push_back(std::move(row));
    pivot_col.push_back(lead);
    out.independent.push_back(static_cast<int>(r));
  }
  return out;
}

} // namespace bary::detail
