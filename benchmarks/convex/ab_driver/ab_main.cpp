// In-process A/B of the cold boolean GJK (run.sh builds it): per cell, `rounds` alternations of the old and the new
// side; prints the medians, the median and range of the per-alternation new/old ratios, and whether every result
// (status, iterations, distance, normal, points) is the same on both sides.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>
double run_old(int, int, int, double*, long*, double*);
double run_new(int, int, int, double*, long*, double*);
int main(int argc, char** argv) {
    int rounds = argc > 1 ? std::atoi(argv[1]) : 7;
    const char* fn[4] = {"box", "hull100", "cylinder", "cone"};
    const char* cn[3] = {"distant", "close", "overlap"};
    for (int f = 0; f < 4; ++f)
        for (int c = 0; c < 3; ++c) {
            std::vector<double> to, tn; double io, in, so, sn; long ho, hn;
            int reps = (f == 0 ? 6 : 3) * (argc > 2 ? std::atoi(argv[2]) : 1);
            for (int r = 0; r < rounds; ++r) {
                to.push_back(run_old(f, c, reps, &io, &ho, &so));
                tn.push_back(run_new(f, c, reps, &in, &hn, &sn));
            }
            std::vector<double> rt; for (int r = 0; r < rounds; ++r) rt.push_back(tn[r] / to[r]);
            std::sort(to.begin(), to.end()); std::sort(tn.begin(), tn.end()); std::sort(rt.begin(), rt.end());
            std::printf("%-8s %-8s old %6.1f new %6.1f ns (median of %d)  new/old median %.3f [%.3f..%.3f]  it %.2f/%.2f hits %ld/%ld  %s\n",
                        fn[f], cn[c], to[rounds / 2], tn[rounds / 2], rounds, rt[rounds / 2], rt[0], rt[rounds - 1], io / 200, in / 200, ho, hn,
                        (so == sn && io == in && ho == hn) ? "same results" : "RESULTS DIFFER");
        }
}
