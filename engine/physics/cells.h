/* The cell stage's core written once (C99 subset): newborn placement, the division's split and the rewrite; what
 * grows and what divides are plug-ins (engine/growth, engine/division), as a cell's fate is (engine/fates); used by
 * engine/backends/cells.cpp (the host reference) and by the cell section of kernels.cl (the device). */
/* Included once per program, after evaluator.h. Per-cell bookkeeping (the field record, centroid, gyration, axis) is
 * double on every backend; positions are the backend's real (rules.single: newborns rounded to float). The
 * includer defines:
 *   SEMLB_CELL_IN               the parameter type of the input element positions
 *   SEMLB_CELL_X(in, e, d)      coordinate d of element e, as double
 *   SEMLB_CELL_OUT / SEMLB_CELL_KEYS   the parameter types of the output positions / keys
 *   SEMLB_CELL_PUT(out, keys, e, x, y, z, info, key)   writes element e of the new state
 * Storage order of the new state: the existing cells in stored order, then the daughters in their mothers'
 * stored order; nothing a cell computes depends on its storage index, so any rank count gives the same cells. */

/* Must equal state.hpp's kSlotBits, kRootIdBits, kMaxDivisionDepth (static_assert in cells.cpp). */
#define SEMLB_CELL_SLOT_BITS 8
#define SEMLB_CELL_ROOT_ID_BITS 20
#define SEMLB_CELL_MAX_DEPTH 36
#define SEMLB_CELL_MAX_ELEMENTS 255 /* kMaxSlots - 1: the most elements a cell holds (growth stops the run beyond) */
#define SEMLB_GROWTH_STREAM 0x67726f77UL /* separates growth draws from the noise stream */
#define SEMLB_JACOBI_SWEEPS 16           /* cyclic sweeps at most; stops early once the off-diagonal is 0 */

SEMLB_DEFINE_RANDOM(double, semlb_uniform64, semlb_gauss64)

/* The most derived parameters (doubles) of a growth law or division rule: the size of its part of the rules. */
#define SEMLB_CELL_RULE_PARAMS 16

/* The cell stage's rules (doubles first: the same layout in C++ and OpenCL C): the scene's growth law and division
 * rule, plug-ins (growth/NAME.h, division/NAME.h) picked by their index in name order; the core here only sums,
 * places newborns, splits and rewrites. */
typedef struct {
  double growth_p[SEMLB_CELL_RULE_PARAMS];   /* the growth law's derived parameters (growth/growth_law.hpp) */
  double division_p[SEMLB_CELL_RULE_PARAMS]; /* the division rule's (division/division_rule.hpp) */
  double offset;                             /* um from the centroid to a newborn element */
  double time;                               /* h: the stage's time, what a law may read (semlb_cell_stage_at) */
  int growth;                                /* the growth law's index in GrowthLaws::names(), -1: no growth */
  int division;                              /* the division rule's index in DivisionRules::names(), -1: no division */
  int single; /* 1: positions are float (newborns rounded to float before division sees them) */
  /* The per-cell fields (effects/cell_fields.hpp) as one record of `fields` doubles per cell, the State's
   * cell_fields in name order; the core reads two at their record index (-1: absent, read as 0 and not written).
   * A new field needs no edit here. */
  int fields;
  int growth_field; /* the growth law's field (growth.clock: h), -1: none */
  int depth_field;  /* division.depth (divisions so far: the id scheme's, state.hpp) */
} semlb_cell_rules;

/* Sets the stage's time (h); the caller (the host) does it before each stage, so every backend's laws read the same
 * double. */
static inline void semlb_cell_stage_at(semlb_cell_rules* r, double time) { r->time = time; }

/* Whether a cell of `type` with `count` elements after growth divides by size: bit `type` of p[0] (a type mask) is
 * set and count >= p[1]. The trigger the shipped division rules share (division/division_rule.hpp
 * read_size_trigger). */
static inline int semlb_cell_divides_by_size(int type, int count, const double* p) {
  return (((long)p[0] >> type) & 1) && count >= (int)p[1];
}

/* The mean of elements [first, first + n) (in slot order, then divided by max(n, 1)). */
static inline void semlb_cell_centroid(SEMLB_CELL_IN in, long first, int n, double* c) {
  c[0] = c[1] = c[2] = 0;
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) c[d] += SEMLB_CELL_X(in, first + k, d);
  for (int d = 0; d < 3; ++d) c[d] /= (double)(n > 1 ? n : 1);
}

/* Element k of a cell after growth: a stored one (k < count) or a newborn, old centroid + offset * a unit
 * vector of three normals keyed by (seed ^ growth stream, element key, step, axis). */
static inline void semlb_cell_element(SEMLB_CELL_IN in, long first, int count, const double* old_centroid,
                                      const semlb_cell_rules* r, SEMLB_ULONG seed, SEMLB_ULONG id, SEMLB_ULONG step,
                                      int k, double* p) {
  if (k < count) {
    for (int d = 0; d < 3; ++d) p[d] = SEMLB_CELL_X(in, first + k, d);
    return;
  }
  SEMLB_ULONG key = (id << SEMLB_CELL_SLOT_BITS) | (SEMLB_ULONG)k;
  double u[3], norm = 0;
  for (int d = 0; d < 3; ++d) {
    u[d] = semlb_gauss64(seed ^ SEMLB_GROWTH_STREAM, key, step, (SEMLB_ULONG)d);
    norm += u[d] * u[d];
  }
  norm = SEMLB_SQRT(norm) + 1e-300;
  for (int d = 0; d < 3; ++d) {
    p[d] = old_centroid[d] + r->offset * u[d] / norm;
    if (r->single) p[d] = (double)(float)p[d];
  }
}

/* The unit eigenvector of the largest eigenvalue of the symmetric g = (g00, g01, g02, g11, g12, g22) by cyclic
 * Jacobi rotations ((0,1), (0,2), (1,2) per sweep; a rotation is skipped when its entry is exactly 0; at most
 * SEMLB_JACOBI_SWEEPS sweeps). Ties between eigenvalues go to the lowest index. The sign makes the largest
 * |component| (the first such) positive. Only +, -, *, / and sqrt: the same bits in C++ and OpenCL C. */
static inline void semlb_cell_long_axis(const double* g, double* axis) {
  double a[3][3] = {{g[0], g[1], g[2]}, {g[1], g[3], g[4]}, {g[2], g[4], g[5]}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < SEMLB_JACOBI_SWEEPS; ++sweep) {
    if (a[0][1] == 0 && a[0][2] == 0 && a[1][2] == 0) break;
    for (int pq = 0; pq < 3; ++pq) {
      int p = pq == 2 ? 1 : 0, q = pq == 0 ? 1 : 2;
      double apq = a[p][q];
      if (apq == 0) continue;
      double theta = (a[q][q] - a[p][p]) / (2 * apq);
      double t = 1 / ((theta < 0 ? -theta : theta) + SEMLB_SQRT(theta * theta + 1));
      if (theta > 1e150 || theta < -1e150) t = 1 / (2 * (theta < 0 ? -theta : theta)); /* theta^2 would overflow */
      if (theta < 0) t = -t;
      double c = 1 / SEMLB_SQRT(t * t + 1), s = t * c;
      for (int k = 0; k < 3; ++k) { /* columns p, q of A J */
        double akp = a[k][p], akq = a[k][q];
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
      }
      for (int k = 0; k < 3; ++k) { /* rows p, q of J^T (A J) */
        double apk = a[p][k], aqk = a[q][k];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
      }
      a[p][q] = a[q][p] = 0;
      for (int k = 0; k < 3; ++k) {
        double vkp = v[k][p], vkq = v[k][q];
        v[k][p] = c * vkp - s * vkq;
        v[k][q] = s * vkp + c * vkq;
      }
    }
  }
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (a[k][k] > a[best][best]) best = k;
  int big = 0;
  for (int d = 1; d < 3; ++d)
    if ((v[d][best] < 0 ? -v[d][best] : v[d][best]) > (v[big][best] < 0 ? -v[big][best] : v[big][best])) big = d;
  double sign = v[big][best] < 0 ? -1.0 : 1.0;
  for (int d = 0; d < 3; ++d) axis[d] = sign * v[d][best];
}

/* Where a dividing cell's elements go. */
typedef struct {
  double centroid[3], axis[3]; /* after growth; the split plane passes through centroid, normal to axis */
  int n;                       /* elements after growth */
  int leave;                   /* elements of the daughter */
  int by_rank;                 /* 1: all on one side (e.g. coincident): halves by rank of projection */
} semlb_cell_split;

static inline double semlb_cell_projection(const double* p, const semlb_cell_split* s) {
  return (p[0] - s->centroid[0]) * s->axis[0] + (p[1] - s->centroid[1]) * s->axis[1] +
         (p[2] - s->centroid[2]) * s->axis[2];
}

/* The division's first half: the centroid (into s->centroid) and the gyration tensor g = (g00, g01, g02, g11, g12,
 * g22), the mean of d d^T, of a cell of `count` stored elements + `births` newborns. The rule then sets s->axis from
 * them (its semlb_division_axis_NAME) before semlb_cell_plan_halves. */
static inline void semlb_cell_gyration(SEMLB_CELL_IN in, long first, int count, int births, const double* old_centroid,
                                       const semlb_cell_rules* r, SEMLB_ULONG seed, SEMLB_ULONG id, SEMLB_ULONG step,
                                       semlb_cell_split* s, double* g) {
  int n = count + births;
  double p[3];
  s->n = n;
  s->centroid[0] = s->centroid[1] = s->centroid[2] = 0;
  for (int i = 0; i < 6; ++i) g[i] = 0;
  for (int k = 0; k < n; ++k) {
    semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, k, p);
    for (int d = 0; d < 3; ++d) s->centroid[d] += p[d];
  }
  for (int d = 0; d < 3; ++d) s->centroid[d] /= (double)n;
  for (int k = 0; k < n; ++k) {
    semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, k, p);
    double x = p[0] - s->centroid[0], y = p[1] - s->centroid[1], z = p[2] - s->centroid[2];
    g[0] += x * x;
    g[1] += x * y;
    g[2] += x * z;
    g[3] += y * y;
    g[4] += y * z;
    g[5] += z * z;
  }
  for (int i = 0; i < 6; ++i) g[i] /= (double)n;
}

/* The division's second half, with s->axis set: the daughter takes the elements with projection > 0 (in slot order),
 * the mother the rest; when one side is empty, the stable order by projection: the first n/2 stay. */
static inline void semlb_cell_plan_halves(SEMLB_CELL_IN in, long first, int count, const double* old_centroid,
                                          const semlb_cell_rules* r, SEMLB_ULONG seed, SEMLB_ULONG id, SEMLB_ULONG step,
                                          semlb_cell_split* s) {
  int n = s->n;
  double p[3];
  s->leave = 0;
  for (int k = 0; k < n; ++k) {
    semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, k, p);
    if (semlb_cell_projection(p, s) > 0) ++s->leave;
  }
  s->by_rank = s->leave == 0 || s->leave == n;
  if (s->by_rank) s->leave = n - n / 2;
}

/* The position of element k in the stable order by projection (ties by slot). */
static inline int semlb_cell_rank(SEMLB_CELL_IN in, long first, int count, const double* old_centroid,
                                  const semlb_cell_rules* r, SEMLB_ULONG seed, SEMLB_ULONG id, SEMLB_ULONG step,
                                  const semlb_cell_split* s, int k) {
  double p[3];
  semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, k, p);
  double pk = semlb_cell_projection(p, s);
  int rank = 0;
  for (int j = 0; j < s->n; ++j) {
    semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, j, p);
    double pj = semlb_cell_projection(p, s);
    if (pj < pk || (!(pk < pj) && j < k)) ++rank;
  }
  return rank;
}

/* Writes a cell's elements after growth and division: the mother's at mother_first as cell index
 * mother_cell, the daughter's (when s) at daughter_first as daughter_cell; keys from the ids. */
static inline void semlb_cell_rewrite(SEMLB_CELL_IN in, long first, int count, int births, const double* old_centroid,
                                      const semlb_cell_rules* r, SEMLB_ULONG seed, SEMLB_ULONG step, SEMLB_ULONG id,
                                      int type, long mother_first, int mother_cell, const semlb_cell_split* s,
                                      SEMLB_ULONG daughter_id, long daughter_first, int daughter_cell,
                                      SEMLB_CELL_OUT out, SEMLB_CELL_KEYS keys) {
  int n = count + births, stay = 0, leave = 0;
  double p[3];
  for (int k = 0; k < n; ++k) {
    semlb_cell_element(in, first, count, old_centroid, r, seed, id, step, k, p);
    int to_daughter = 0, slot = k;
    if (s) {
      if (s->by_rank) {
        int rank = semlb_cell_rank(in, first, count, old_centroid, r, seed, id, step, s, k);
        to_daughter = rank >= n / 2;
        slot = to_daughter ? rank - n / 2 : rank;
      } else {
        to_daughter = semlb_cell_projection(p, s) > 0;
        slot = to_daughter ? leave++ : stay++;
      }
    }
    if (to_daughter)
      SEMLB_CELL_PUT(out, keys, daughter_first + slot, p[0], p[1], p[2], semlb_info_pack(daughter_cell, type),
                     (daughter_id << SEMLB_CELL_SLOT_BITS) | (SEMLB_ULONG)slot);
    else
      SEMLB_CELL_PUT(out, keys, mother_first + slot, p[0], p[1], p[2], semlb_info_pack(mother_cell, type),
                     (id << SEMLB_CELL_SLOT_BITS) | (SEMLB_ULONG)slot);
  }
}
