"""Hand-made bad inputs, run as a user would: every case must end with exit 2 naming the key,
option or row the user wrote (or exit 0 where the input is valid), leave a user folder intact
and no temporary directory. Usage, from the repository root after `cargo build --release`:
`python3 scripts/bad-inputs.py` (cases run in a scratch folder under /tmp)."""
import subprocess, os, re, time, shutil, sys, tempfile
B=os.path.abspath(os.environ.get("RVLIFE_BIN", "target/release/rvlife"))
WORK=tempfile.mkdtemp(prefix="rvlife-bad-")
base=subprocess.run([B,"example"],capture_output=True,text=True).stdout
base=re.sub(r"(?m)^enabled = true","enabled = false",base)
def setk(text, table, key, val):
    out=[];cur="";done=False
    for l in text.splitlines():
        m=re.match(r"^\[([^\]]+)\]",l.strip())
        if m: cur=m.group(1).strip()
        k=l.split("=")[0].strip() if "=" in l and not l.strip().startswith("#") else None
        if not done and cur==table and k==key:
            out.append(f"{key} = {val}");done=True
        else: out.append(l)
    if not done:
        out2=[]
        for l in out:
            out2.append(l)
            m=re.match(r"^\[([^\]]+)\]",l.strip())
            if m and m.group(1).strip()==table and not done:
                out2.append(f"{key} = {val}"); done=True
        out=out2
    assert done, (table,key)
    return "\n".join(out)+"\n"
cases=[]
def C(name, edits=(), args=("te",), files=None, raw=None):
    cases.append((name, edits, args, files, raw))
for t,k,v in [("cycloid","pins","2"),("cycloid","pins","1001"),("cycloid","pins","40.5"),("cycloid","eccentricity_mm","0"),
  ("cycloid","eccentricity_mm","-1"),("cycloid","eccentricity_mm","nan"),("cycloid","eccentricity_mm","0.014"),("cycloid","eccentricity_mm","0.033"),
  ("cycloid","eccentricity_mm","40"),("cycloid","pin_circle_radius_mm","1e308"),("cycloid","pin_circle_radius_mm","0.001"),("cycloid","pin_radius_mm","0"),
  ("cycloid","pin_radius_mm","30"),("cycloid","width_mm","1e-12"),("cycloid","width_mm","1e6"),("cycloid.modification","equidistant_mm","-1"),
  ("cycloid.modification","equidistant_mm","1"),("cycloid.modification","offset_mm","2.75"),("cycloid.modification","offset_mm","-2.75"),
  ("cycloid.modification","rotation_deg","-2e8"),("cycloid.modification","rotation_deg","1e300"),("cycloid.modification","rotation_deg","4"),
  ("materials.disc","youngs_modulus_gpa","0"),("materials.disc","poisson_ratio","0.5"),("materials","max_contact_pressure_mpa","0"),
  ("reducer","rated_torque_nm","1e300"),("reducer","rated_torque_nm","0"),("reducer","input_speed_rpm","1e300"),("reducer","input_speed_rpm","0"),
  ("reducer","sun_teeth","0"),("reducer","planets","13"),("load","torque_nm","1e12"),("load","torque_nm","12700"),("load","torque_nm","-12700"),
  ("load","torque_nm","nan"),("wear","archard_coefficient_mm3_per_n_m","0"),("wear","stage_hours","[]"),("wear","stage_hours","[0.0, -1.0]"),
  ("wear","stage_hours","[1e8]"),("wear","profile_update_hours","1e-9"),("wear","max_wear_step_um","0.001"),("wear","crank_steps_per_mesh_cycle","1"),
  ("te","samples_per_mesh_cycle","1"),("te","samples_per_mesh_cycle","100000"),("te","measuring_torque_fraction","0.9"),
  ("dynamics.load","amplitude_nm","5e5"),("dynamics","end_time_s","1e9"),("dynamics","relative_tolerance","0"),("fem","flank_element_size_mm","0.001"),
  ("fem","centre_hole_diameter_mm","200"),("dynamics.inertia","crank_bore_radius_mm","19.0"),("contact","law","\"x\""),("contact","support","\"x\""),
  ("contact","band_force_n","-1"),("reducer.gears","pressure_angle_deg","90"),("reducer.gears","mesh_stiffness_n_per_um","0"),
  ("reducer.bearings","crank_disc_stiffness_n_per_um","5"),("reducer.bearings","clearance_um","1e6"),("wear","profile_update_hours","-1"),
  ("wear","pin_rolling_fraction","2"),("wear","model","\"x\""),("load","kind","\"x\"")]:
    if t.startswith("dynamics") and k!="crank_bore_radius_mm":
        C(f"{t}.{k}={v}", [(t,k,v)], ("dynamics",))
    elif t=="fem" or k=="crank_bore_radius_mm":
        C(f"{t}.{k}={v}", [(t,k,v),("fem","enabled","true")])
    else:
        C(f"{t}.{k}={v}", [(t,k,v)])
C("te.loaded_torque_nm=1e30", raw="[te]\nloaded_torque_nm = 1e30\n")
C("archard=1e6 te --hours 2e-9", [("wear","archard_coefficient_mm3_per_n_m","1e6")], ("te","--hours","2e-9"))
C("unknown key", raw="[cycloid]\nbogus = 1\n")
C("duplicate key", raw="[reducer]\nplanets = 2\n")
C("contact.load_share=2 rigid", [("contact","support","\"rigid\"")], raw="[contact]\nload_share = 2.0\n")
def dc(rows): return "duration_s,torque_nm,speed_rpm\n"+rows
for n,rows in [("dc 1e308",dc("1e308,412,1500\n1e308,-412,1500\n")),("dc negative",dc("-1,412,1500\n")),("dc empty",dc("")),
    ("dc header","a,b,c\n1,2,3\n"),("dc nan torque",dc("1,nan,1500\n")),("dc speed 1e300",dc("1,412,1e300\n")),
    ("dc 1e6 rows",dc("".join(f"1,{100+i*1e-4:.4f},1500\n" for i in range(1000000))))]:
    C(n, [("load","kind","\"duty_cycle\"")], files={"dc.csv":rows}, raw="[load]\nfile = \"dc.csv\"\n")
for n,tab in [("table 1e300","time_s,torque_nm\n0,0\n1,1e300\n"),("table unsorted","time_s,torque_nm\n0,0\n1,5\n0.5,3\n")]:
    C(n,[("dynamics.load","kind","\"table\"")],("dynamics",),files={"t.csv":tab},raw="[dynamics.load]\nfile = \"t.csv\"\n")
for a in [("te","--torque-nm","1e30"),("te","--torque-nm","nan"),("contact","--crank-deg","inf","--torque-nm","1"),("te","--hours","1e12"),
   ("te","--hours","-1"),("te","--wear-um","-1"),("te","--wear-um","1e9"),("calibrate","--target-wear-um","1e9"),("calibrate","--target-wear-um","-1"),
   ("calibrate","--target-wear-um","0"),("hysteresis","--levels","0"),("hysteresis","--levels","1000000"),("profile","--out","x.txt"),
   ("profile","--out","."),("profile","--out","missing/x.csv"),("run","--out","."),("run","--out",".."),("run","--out","/proc/x"),
   ("run","--out","userdir","--force"),("--work-budget-min","0","te"),("--work-budget-min","nan","te"),
   ("dynamics","--load","constant","--torque-nm","1e30"),("te","--hours","1e6")]:
    C(" ".join(a), (), a)
C("missing config", (), ("te",), raw=None); cases[-1]=("missing config",(),("te","/nonexistent.toml"),None,"MISSING")
C("config is dir", (), ("te","."), None, "DIR"); cases[-1]=("config is dir",(),("te","."),None,"DIR")
res=[]
for i,(name,edits,args,files,raw) in enumerate(cases):
    d=f"{WORK}/c{i}"; shutil.rmtree(d,ignore_errors=True); os.makedirs(d)
    os.makedirs(f"{d}/userdir"); open(f"{d}/userdir/mine.txt","w").write("x")
    text=base
    for t,k,v in edits: text=setk(text,t,k,v)
    if raw and raw.startswith("[reducer]\nplanets"): text=text.replace("[reducer]\n","[reducer]\nplanets = 2\n",1)
    if raw and raw.startswith("[cycloid]\nbogus"): text=text.replace("[cycloid]\n","[cycloid]\nbogus = 1\n",1)
    if raw and raw.startswith("[te]"): text=text.replace("[te]\n","[te]\nloaded_torque_nm = 1e30\n",1)
    if raw and raw.startswith("[contact]\nload_share"): text=text.replace("[contact]\n","[contact]\nload_share = 2.0\n",1)
    if raw and raw.startswith("[load]\nfile"): text=text.replace("[load]","[load]\nfile = \"dc.csv\"",1); text=re.sub(r"(?m)^torque_nm = 412.0.*$","",text)
    if raw and raw.startswith("[dynamics.load]\nfile"): text=text.replace("[dynamics.load]","[dynamics.load]\nfile = \"t.csv\"",1)
    open(f"{d}/c.toml","w").write(text)
    for f,c in (files or {}).items(): open(f"{d}/{f}","w").write(c)
    argv=list(args)
    if raw not in ("MISSING","DIR"):
        # insert config after the subcommand
        if argv[0]=="--work-budget-min": argv=argv[:3]+["c.toml"]+argv[3:]
        else: argv=[argv[0],"c.toml"]+argv[1:]
    if argv[0] in ("run",) and "--out" not in argv: argv+=["--out","r"]
    t0=time.time()
    try:
        p=subprocess.run([B]+argv,cwd=d,capture_output=True,text=True,timeout=300); rc=p.returncode; err=p.stderr.strip().splitlines()[-1:] 
    except subprocess.TimeoutExpired:
        rc="TIMEOUT"; err=[""]
    dt=time.time()-t0
    intact=open(f"{d}/userdir/mine.txt").read()=="x"
    left=[x for x in os.listdir(d) if x.startswith(".rvlife-tmp")]
    res.append((name,rc,dt,intact,left,(err[0] if err else "")[:150]))
    print(f"{rc!s:>7} {dt:6.1f}s {name:45s} {(err[0] if err else '')[:150]}",flush=True)
from collections import Counter
print(Counter(str(r[1]) for r in res), "cases", len(res), "user data intact", all(r[3] for r in res), "tmp left", sum(len(r[4]) for r in res))
