"""The reference Jacobian of `cylinder_rim_against_a_50_digit_reference`
(src/query/sphere_jacobian_tests.rs): a sphere against a cylinder (radius 0.3, length 0.9),
alpha* and x* from the closed form of each feature (rims, side, caps) in 50-digit arithmetic,
differentiated by central differences of step 1e-20. Columns printed in the test's order
(cylinder first). Needs mpmath (`pip install mpmath`)."""
from mpmath import mp, mpf, sqrt, matrix
mp.dps = 50
r2=[-0.7255866017616059, -0.9956957750827253, 0.14220121956942955]; q2=[-0.6109182803633515, 0.7353940909917729, 0.13053608200238354, -0.26504971300819125]
r1=[0.5810473013172992, -0.2615950994406162, -0.8156480961734345]; q1=[0.12955655278787703, 0.544323630878023, 0.7074133943064167, 0.11100930206841308]
R=mpf(0.401383824495138); rho=mpf('0.3'); h=mpf('0.45')
def rot(q):
    n=sqrt(sum(x*x for x in q)); w,x,y,z=[v/n for v in q]
    return matrix([[1-2*(y*y+z*z),2*(x*y-w*z),2*(x*z+w*y)],[2*(x*y+w*z),1-2*(x*x+z*z),2*(y*z-w*x)],[2*(x*z-w*y),2*(y*z+w*x),1-2*(x*x+y*y)]])
def sol(v):
    rs=matrix(v[0:3]); rb=matrix(v[7:10]); Q=rot(v[10:14])
    q=Q.T*(rs-rb)
    pa=q[0]; pr=sqrt(q[1]**2+q[2]**2)
    best=None
    for (va,vr) in [(h,rho),(-h,rho)]:
        A=va*va+vr*vr-R*R; B=pa*va+pr*vr; C=pa*pa+pr*pr
        disc=B*B-A*C
        if disc<0: continue
        for a in [(B-sqrt(disc))/A,(B+sqrt(disc))/A]:
            if a>0 and (best is None or a<best[0]):
                # valid if normal (p - a v) in the vertex's normal cone
                ma=pa-a*va; mr=pr-a*vr
                if ma*va>0 and mr>0: best=(a,va,vr,'rim')
    a=pr/(rho+R)
    if abs(pa)<=a*h and (best is None or a<best[0]): best=(a,pa/a,rho,'side')
    a=abs(pa)/(h+R)
    if pr<=a*rho and (best is None or a<best[0]): best=(a,h*(1 if pa>0 else -1),pr/a,'cap')
    a,va,vr,kind=best
    global KIND; KIND=kind
    u=matrix([0,q[1]/pr,q[2]/pr])
    pt=matrix([va,0,0])+u*vr
    x=rb+Q*pt*a
    return [x[0],x[1],x[2],a]
v=[mpf(t) for t in r1+q1+r2+q2]

print(sol(v), KIND)
eps=mpf('1e-20')
J=[]
for c in range(14):
    vp=list(v); vm=list(v); vp[c]+=eps; vm[c]-=eps
    a=sol(vp); b=sol(vm)
    J.append([(a[i]-b[i])/(2*eps) for i in range(4)])
for i in range(4): print([float(J[(c+7)%14][i]) for c in range(14)])
