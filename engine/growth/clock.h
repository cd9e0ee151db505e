/* "clock": a cell of a growing type adds one element every period h of its clock (growth.clock, h), up to
 * max_elements; a full cell's clock runs on. With a proliferative front (Du et al. 2018's wave along x, docs/engine.md)
 * only a cell whose centroid x <= x0 + speed * time (um) grows; ahead of it the cell is quiescent and its clock stands.
 * C99 subset, no include guard: included by clock.cpp (namespace cellrules) and pasted into the OpenCL cell section
 * (growth_laws.cl). Parameters (doubles, growth_law.hpp): (period h, type mask, max_elements, front 0/1, x0 um,
 * speed um/h). */
static inline int semlb_growth_clock(int type, int count, const double* centroid, double time, double elapsed,
                                     const double* p, double* clock) {
  if (!(((long)p[1] >> type) & 1)) return 0;
  if (p[3] != 0 && !(centroid[0] <= p[4] + p[5] * time)) return 0;
  int births = 0, max_elements = (int)p[2];
  *clock += elapsed;
  for (; *clock >= p[0]; *clock -= p[0])
    if (count + births < max_elements) ++births;
  return births;
}
