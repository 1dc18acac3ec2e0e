"""The table of docs/attractors.md ("What the design value changes") from a sweep CSV of
data/studies/tables-2-3-attractors.json: python3 docs/plot/attractors_table.py t23.csv"""
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(len(rows), "points")
multi = sum(int(r['attractors']) > 1 for r in rows)
above = sum(float(r['F_m_max']) > 1.01 * float(r['F_m']) for r in rows)
flag = sum(r['multistable'] == '1' for r in rows)
unset = sum(int(r['unsettled']) > 0 for r in rows)
print("more than one attractor:", multi, "F_m_max > 1.01 F_m:", above, "flagged multistable:", flag, "with unsettled groups:", unset)
for eps in ['0.1', '0.2', '0.3', '0.5']:
    for name, cond in (("e_r < 0.3", lambda e: e < 0.3), ("e_r > 0.3", lambda e: e > 0.3)):
        sel = [r for r in rows if r['eps'] == eps and cond(float(r['e_r']))]
        if not sel: continue
        best = max(sel, key=lambda r: float(r['F_m_max']))
        print("| %s | %s | %.3f | %.3f (fc %s, e_r %s, f_r %s) | %.0f %% |" % (eps, name,
              max(float(r['F_m']) for r in sel), float(best['F_m_max']), best['fc'], best['e_r'], best['f_r'],
              100.0 * sum(int(r['attractors']) > 1 for r in sel) / len(sel)))
