"""The HTML, CSS and script of the branch explorer page (see :mod:`.explore`): no framework, no network.

The script reads the page's JSON (``script.mcx-data``), draws the diagram and the mechanism
in SVG and keeps every drawn element's coordinates in metres in ``data-xy`` (``x y[ z]``
per point, ``;`` between points), so a test can read the pose back from the page.
"""

from __future__ import annotations

import html

from .drawing3d import VIEWS

__all__ = ["render", "VIEW_AXES"]

#: Spatial view -> [horizontal axis index, vertical axis index, their names, sign of a moment seen in the view].
VIEW_AXES = {v: [h, w, "xyz"[h], "xyz"[w], 1 if (h, w, n) in ((1, 2, 0), (2, 0, 1), (0, 1, 2)) else -1]
             for v, (h, w, n) in VIEWS.items()}

_CSS = """
#TOKEN{font:13px/1.35 system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;color:#222}
#TOKEN h2{font-size:16px;margin:4px 0 6px}
#TOKEN .row{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}
#TOKEN .panel{border:1px solid #ddd;border-radius:4px;padding:6px;background:#fff}
#TOKEN svg{display:block;background:#fff;-webkit-user-select:none;user-select:none}
#TOKEN .sp,#TOKEN .vt,#TOKEN .legend{-webkit-user-select:none;user-select:none}
#TOKEN .dg{box-sizing:content-box}
#TOKEN .views{display:flex;flex-wrap:wrap;gap:4px}
#TOKEN .views.d3{display:grid;grid-template-columns:auto auto}
#TOKEN .vt{font-size:11px;color:#555;text-align:center}
#TOKEN table{border-collapse:collapse;font-size:12px}
#TOKEN td,#TOKEN th{padding:1px 6px;text-align:left;border-bottom:1px solid #eee}
#TOKEN td.n{text-align:right;font-variant-numeric:tabular-nums}
#TOKEN .sp button{margin:2px;padding:1px 6px;font-size:12px;cursor:pointer;border:1px solid #aaa;border-radius:3px;
 background:#f7f7f7}
#TOKEN .sp button.on{background:#ffe8c2;border-color:#d08000}
#TOKEN .note{color:#8a4b00;font-size:12px}
#TOKEN .status{font-weight:600}
#TOKEN .legend span{display:inline-block;margin-right:10px;font-size:12px}
#TOKEN .legend i{display:inline-block;width:14px;height:6px;margin-right:4px;vertical-align:middle;border-radius:2px}
#TOKEN input[type=range]{width:100%}
#TOKEN .tables{max-height:380px;overflow:auto}
#TOKEN.compact .tables{max-height:250px}
"""

_BODY = """
<h2 class="title"></h2>
<div class="notes note"></div>
<div class="row">
 <div class="panel dg">
  <div>x <select class="xsel"></select> y <select class="ysel"></select>
   <span class="bsel-wrap">branch <select class="bsel"></select></span></div>
  <svg class="diagram"></svg>
  <div class="blegend legend"></div>
  <input class="slider" type="range" min="0" max="0" step="1" value="0" aria-label="row along the branch">
  <div class="sp"></div>
 </div>
 <div class="panel">
  <div class="status"></div>
  <div class="views"></div>
  <div class="bodies legend"></div>
 </div>
 <div class="panel tables">
  <table class="loads"></table>
  <table class="values"></table>
 </div>
</div>
"""

_JS = r"""
(function(){
"use strict";
var root=document.getElementById("TOKEN");
var D=JSON.parse(root.querySelector("script.mcx-data").textContent);
var NS="http://www.w3.org/2000/svg", C=D.compact;
var MARK={LP:["circle","#d62728"],BP:["square","#9467bd"],CP:["diamond","#2ca02c"],EP:["cross","#666666"],UZ:["triangle",
 "#ff7f0e"],LPC:["circle","#d62728"],PD:["square","#9467bd"],NS:["diamond","#2ca02c"],HB:["star","#1f77b4"]};
var LINE=["#000000","#1f77b4","#ff7f0e","#2ca02c","#9467bd","#8c564b","#e377c2","#7f7f7f"];
var B=D.branches, cur={b:0,r:0}, fixed={b:0,r:0}, dg=null;
function q(s){return root.querySelector(s);}
function el(tag,at,parent,text){var e=document.createElementNS(NS,tag);for(var k in at)e.setAttribute(k,at[k]);
 if(text!==undefined)e.textContent=text;if(parent)parent.appendChild(e);return e;}
function h(tag,at,parent,text){var e=document.createElement(tag);for(var k in at)e.setAttribute(k,at[k]);
 if(text!==undefined)e.textContent=text;if(parent)parent.appendChild(e);return e;}
function fmt(v){if(!isFinite(v))return String(v);var a=Math.abs(v);
 return (a!==0&&(a>=1e6||a<1e-3))?v.toExponential(4):String(+v.toPrecision(6));}
function load(v,u){var a=Math.abs(v);if(u.split(" ")[0]!=="N")return fmt(v)+" "+u;
 if(a>=1e6)return fmt(v/1e6)+" M"+u;if(a>=1e3)return fmt(v/1e3)+" k"+u;return fmt(v)+" "+u;}
function unit(b,n){return (B[b].units&&B[b].units[n])||"";}
// a family of cycles draws a state as its max and min over each orbit (columns max_X, min_X)
function amp(br,n){return br.cycle&&br.cycle.states.indexOf(n)>=0?[br.columns["max_"+n],br.columns["min_"+n]]:null;}
function shown(b,n,v){return unit(b,n)==="rad"?v*180/Math.PI:v;}
function axisLabel(n){var u="";for(var k=0;k<B.length;k++)if(unit(k,n)){u=unit(k,n);break;}
 return u==="rad"?n+" (deg)":(u?n+" ("+u+")":n);}
function xy(p){return p.join(" ");}
function xys(ps){return ps.map(xy).join(";");}
// ---------------------------------------------------------------- the diagram
var cols=[];B.forEach(function(br){Object.keys(br.columns).concat(br.cycle?br.cycle.states:[]).forEach(function(n){
 if(cols.indexOf(n)<0)cols.push(n);});});
var xsel=q(".xsel"),ysel=q(".ysel"),bsel=q(".bsel");
cols.forEach(function(n){h("option",{value:n},xsel,axisLabel(n));h("option",{value:n},ysel,axisLabel(n));});
xsel.value=D.axes[0];ysel.value=D.axes[1];
B.forEach(function(br,k){h("option",{value:k},bsel,br.name);});
if(B.length<2)q(".bsel-wrap").style.display="none";
var W=C?430:560,H=C?300:400,ML=68,MR=14,MT=12,MB=42;
q(".dg").style.width=W+"px";  // the special points' buttons wrap under the diagram, not across the page
function ticks(lo,hi){var span=hi-lo,step=Math.pow(10,Math.floor(Math.log10(span/5)));
 [1,2,2.5,5,10].some(function(m){if(span/(step*m)<=6){step*=m;return true;}return false;});
 var t=[],v=Math.ceil(lo/step)*step;for(;v<=hi+1e-9*step;v+=step)t.push(Math.abs(v)<1e-12*step?0:v);return t;}
function range(n){var lo=Infinity,hi=-Infinity;B.forEach(function(br,k){var a=amp(br,n);
 (a||[br.columns[n]]).forEach(function(c){if(!c)return;c.forEach(function(v){v=shown(k,n,v);if(v<lo)lo=v;if(v>hi)hi=v;});});});
 if(!(hi>lo)){var d=Math.abs(lo)*0.05||1;lo-=d;hi+=d;}var p=0.04*(hi-lo);return [lo-p,hi+p];}
function segClass(br,i){var a=br.n_unstable[i],b=br.n_unstable[i+1],la=br.labels[i],lb=br.labels[i+1];
 return ((a>0&&b>0)||(a>0&&lb==="LP")||(b>0&&la==="LP"))?"u":"s";}
function marker(g,kind,x,y,colour,at){var s=5,e;
 if(kind==="square")e=el("rect",{x:x-s,y:y-s,width:2*s,height:2*s},g);
 else if(kind==="diamond")e=el("polygon",{points:[x,y-s-1,x+s+1,y,x,y+s+1,x-s-1,y].join(" ")},g);
 else if(kind==="triangle")e=el("polygon",{points:[x,y-s-1,x+s,y+s,x-s,y+s].join(" ")},g);
 else if(kind==="star"){var p=[];for(var k=0;k<10;k++){var a=Math.PI*k/5-Math.PI/2,r=k%2?0.45*(s+2):s+2;
  p.push(x+r*Math.cos(a),y+r*Math.sin(a));}e=el("polygon",{points:p.join(" ")},g);}
 else if(kind==="cross")e=el("path",{d:"M"+(x-s)+" "+(y-s)+"L"+(x+s)+" "+(y+s)+"M"+(x-s)+" "+(y+s)+"L"+(x+s)+" "+(y-s)},g);
 else e=el("circle",{cx:x,cy:y,r:s},g);
 e.setAttribute("fill",kind==="cross"?"none":"#fff");e.setAttribute("stroke",colour);e.setAttribute("stroke-width","2");
 for(var k in at)e.setAttribute(k,at[k]);return e;}
function drawDiagram(){
 var svg=q(".diagram");svg.innerHTML="";svg.setAttribute("width",W);svg.setAttribute("height",H);
 svg.setAttribute("viewBox","0 0 "+W+" "+H);
 var xn=xsel.value,yn=ysel.value,xr=range(xn),yr=range(yn);
 var sx=function(v){return ML+(v-xr[0])/(xr[1]-xr[0])*(W-ML-MR);},sy=function(v){return H-MB-(v-yr[0])/(yr[1]-yr[0])*(H-MT-MB);};
 var g=el("g",{"font-size":"11","fill":"#333"},svg);
 ticks(xr[0],xr[1]).forEach(function(t){var x=sx(t);el("line",{x1:x,x2:x,y1:MT,y2:H-MB,stroke:"#eee"},g);
  el("text",{x:x,y:H-MB+14,"text-anchor":"middle"},g,fmt(t));});
 ticks(yr[0],yr[1]).forEach(function(t){var y=sy(t);el("line",{x1:ML,x2:W-MR,y1:y,y2:y,stroke:"#eee"},g);
  el("text",{x:ML-4,y:y+4,"text-anchor":"end"},g,fmt(t));});
 el("rect",{x:ML,y:MT,width:W-ML-MR,height:H-MT-MB,fill:"none",stroke:"#888"},g);
 el("text",{x:(ML+W-MR)/2,y:H-8,"text-anchor":"middle","font-size":"12"},g,axisLabel(xn));
 el("text",{x:14,y:(MT+H-MB)/2,"text-anchor":"middle","font-size":"12",transform:"rotate(-90 14 "+(MT+H-MB)/2+")"},g,
 axisLabel(yn));
 var px=[],marks=[],low=[];
 B.forEach(function(br,k){var X=br.columns[xn],a=amp(br,yn),Ys=a||[br.columns[yn]];px.push(null);low.push(null);
  if(!X||!Ys[0])return;
  Ys.forEach(function(Y,e){
  var P=X.map(function(v,i){return [sx(shown(k,xn,v)),sy(shown(k,yn,Y[i]))];});if(e)low[k]=P;else px[k]=P;
  var colour=LINE[k%LINE.length],w=("t" in br.columns)?1.2:2,i=0,n=P.length;
  while(i<n-1){var c=segClass(br,i),j=i;while(j<n-1&&segClass(br,j)===c)j++;
   el("polyline",{points:P.slice(i,j+1).map(xy).join(" "),fill:"none",stroke:colour,"stroke-width":w,
    "stroke-dasharray":c==="u"?"6 4":"none","data-branch":k,"data-curve":a?(e?"min":"max"):"value"},svg);i=j;}
  if(n===1)el("circle",{cx:P[0][0],cy:P[0][1],r:2,fill:colour},svg);
  br.special.forEach(function(s){var m=MARK[s.label]||["star","#1f77b4"],p=P[s.row];
   var at={"class":"mcx-sp","data-point":s.name,"data-branch":k,"data-row":s.row};if(a)at["data-curve"]=e?"min":"max";
   var q=marker(svg,m[0],p[0],p[1],m[1],at);
   q.style.cursor="pointer";el("title",{},q,br.name+": "+s.tag);
   if(!e)marks.push({x:p[0],y:p[1],text:s.short||s.tag,colour:m[1],b:k,row:s.row});});});});
 placeLabels(svg,marks,px.concat(low));
 dg={px:px,low:low,svg:svg,cursor:el("circle",{r:7,fill:"none",stroke:"#ff7f0e","stroke-width":2.5,"class":"mcx-cursor"},svg)};
 placeCursor();}
// Labels of the special points: each beside its marker, inside the plot frame, clear of every marker and of the
// labels placed before it, covering as few of the branches' points as it can (the least-cost place on rings
// around the marker); one placed away from its marker gets a leader line. Each label's box is kept in data-box.
var LH=14,GAP=2;
function placeLabels(svg,marks,px){
 var frame=[ML,MT,W-MR,H-MB],cell=4,nx=Math.ceil(W/cell)+1,ny=Math.ceil(H/cell)+1,sum=new Float64Array((nx+1)*(ny+1));
 function add(x,y){var i=Math.floor(x/cell),j=Math.floor(y/cell);if(i>=0&&j>=0&&i<nx&&j<ny)sum[(j+1)*(nx+1)+i+1]+=1;}
 px.forEach(function(P){if(!P)return;for(var i=0;i<P.length;i++){add(P[i][0],P[i][1]);if(i+1<P.length){
  var dx=P[i+1][0]-P[i][0],dy=P[i+1][1]-P[i][1],n=Math.min(200,Math.floor(Math.hypot(dx,dy)/cell));
  for(var k=1;k<n;k++)add(P[i][0]+dx*k/n,P[i][1]+dy*k/n);}}});
 for(var j=1;j<=ny;j++)for(var i=1;i<=nx;i++)sum[j*(nx+1)+i]+=sum[(j-1)*(nx+1)+i]+sum[j*(nx+1)+i-1]-sum[(j-1)*(nx+1)+i-1];
 function covered(b){var i0=Math.max(0,Math.floor(b[0]/cell)),j0=Math.max(0,Math.floor(b[1]/cell)),
  i1=Math.min(nx,Math.ceil(b[2]/cell)),j1=Math.min(ny,Math.ceil(b[3]/cell));if(i1<=i0||j1<=j0)return 0;
  return sum[j1*(nx+1)+i1]-sum[j0*(nx+1)+i1]-sum[j1*(nx+1)+i0]+sum[j0*(nx+1)+i0];}
 function meets(b,o){return b[0]<o[2]&&b[2]>o[0]&&b[1]<o[3]&&b[3]>o[1];}
 var taken=marks.map(function(m){return [m.x-7,m.y-7,m.x+7,m.y+7];});
 marks.forEach(function(m){
  var t=el("text",{x:0,y:0,"font-size":"11",fill:m.colour,"class":"mcx-label","dominant-baseline":"central",
   "text-anchor":"middle","data-branch":m.b,"data-row":m.row},svg,m.text);
  var w=(t.getComputedTextLength&&t.getComputedTextLength())||6.5*m.text.length;w+=2*GAP;var hh=LH+2*GAP;
  var best=null,bc=Infinity,fall=null,fc=Infinity;
  for(var r=0;r<=Math.max(W,H);r+=(r?LH/2:8)){for(var d=0;d<(r?16:1);d++){var a=2*Math.PI*d/16,u=Math.cos(a),v=-Math.sin(a);
   var cx=m.x+r*u+0.5*w*u,cy=m.y+r*v+0.5*hh*v,b=[cx-w/2,cy-hh/2,cx+w/2,cy+hh/2];
   if(b[0]<frame[0]||b[2]>frame[2]||b[1]<frame[1]||b[3]>frame[3])continue;
   var clash=taken.filter(function(o){return meets(b,o);}).length,cost=r+6*covered(b);
   if(!clash&&cost<bc){bc=cost;best=[cx,cy,r];}
   if(cost+1e6*clash<fc){fc=cost+1e6*clash;fall=[cx,cy,r];}}
   if(best&&r>bc)break;}
  var c=best||fall||[m.x,m.y-LH,0];
  t.setAttribute("x",c[0]);t.setAttribute("y",c[1]);
  var box=[c[0]-w/2,c[1]-hh/2,c[0]+w/2,c[1]+hh/2];taken.push(box);
  t.setAttribute("data-box",box.map(function(v){return v.toFixed(1);}).join(" "));
  if(c[2]>12){var ex=Math.max(box[0]+GAP,Math.min(box[2]-GAP,m.x)),ey=Math.max(box[1]+GAP,Math.min(box[3]-GAP,m.y));
   svg.insertBefore(el("line",{x1:m.x,y1:m.y,x2:ex,y2:ey,stroke:m.colour,"stroke-width":0.8,"class":"mcx-leader"}),t);}});}
function placeCursor(){if(!dg)return;var P=dg.px[cur.b],c=dg.cursor;
 if(!P){c.setAttribute("visibility","hidden");return;}
 c.setAttribute("visibility","visible");c.setAttribute("cx",P[cur.r][0]);c.setAttribute("cy",P[cur.r][1]);
 c.setAttribute("data-branch",cur.b);c.setAttribute("data-row",cur.r);}
function nearest(ev){var r=dg.svg.getBoundingClientRect(),x=(ev.clientX-r.left)*W/r.width,y=(ev.clientY-r.top)*H/r.height;
 var best=null,bd=30*30;dg.px.concat(dg.low).forEach(function(P,j){if(!P)return;var k=j%B.length;P.forEach(function(p,i){
  var d=(p[0]-x)*(p[0]-x)+(p[1]-y)*(p[1]-y);if(d<bd){bd=d;best={b:k,r:i};}});});return best;}
var svgD=q(".diagram");
svgD.addEventListener("mousemove",function(ev){var n=nearest(ev);if(n)show(n.b,n.r);});
svgD.addEventListener("mouseleave",function(){show(fixed.b,fixed.r);});
svgD.addEventListener("click",function(ev){var t=ev.target,n;
 if(t.getAttribute&&t.getAttribute("data-point"))n={b:+t.getAttribute("data-branch"),r:+t.getAttribute("data-row")};
 else n=nearest(ev);if(n)fix(n.b,n.r);});
xsel.addEventListener("change",drawDiagram);ysel.addEventListener("change",drawDiagram);
bsel.addEventListener("change",function(){fix(+bsel.value,0);});
var slider=q(".slider");slider.addEventListener("input",function(){fix(cur.b,+slider.value);});
// ---------------------------------------------------------------- special points and legends
var sp=q(".sp");
B.forEach(function(br,k){if(!br.special.length)return;var d=h("div",{},sp);h("span",{},d,
 (B.length>1?br.name+": ":"special points: "));
 br.special.forEach(function(s){var v=br.vary&&br.columns[br.vary]?" ("+br.vary+" = "+fmt(shown(k,br.vary,
 br.columns[br.vary][s.row]))+")":"";
  var b=h("button",{type:"button","data-point":s.name,"data-branch":k,"data-row":s.row},d,s.tag+v);
  b.addEventListener("click",function(){fix(k,s.row);});});});
var bl=q(".blegend");
B.forEach(function(br,k){var s=h("span",{},bl);var i=h("i",{},s);i.style.background=LINE[k%LINE.length];
 var st=br.n_unstable.some(function(v){return v>=0;})?" (solid stable, dashed unstable)":"";
 s.appendChild(document.createTextNode(br.name+st));});
var bodies=q(".bodies");
D.bodies.forEach(function(b){var s=h("span",{},bodies);var i=h("i",{},s);i.style.background=b.colour;
 s.appendChild(document.createTextNode(b.name));});
// ---------------------------------------------------------------- the mechanism
var views=[];
(function(){var box=q(".views"),names=(D.dim===3?["front","side","top"]:["plane"]).filter(function(v){return D.views[v];});
 // spatial: the three views two by two, so that the mechanism stands beside the diagram (at 1400 x 900 too)
 if(D.dim===3)box.className+=" d3";
 var w=D.dim===3?(C?210:340):(C?330:460),hh=D.dim===3?(C?180:290):(C?280:390);
 var s=Math.min.apply(null,names.map(function(v){var lim=D.views[v];return Math.min(w/(lim[1]-lim[0]),hh/(lim[3]-lim[2]));}));
 names.forEach(function(v){var lim=D.views[v],wrap=h("div",{},box);
  var svg=el("svg",{width:w,height:hh,viewBox:"0 0 "+w+" "+hh,"class":"mech","data-view":v},wrap);
  var ax=D.dim===3?D.view_axes[v]:[0,1,"x","y",1];
  h("div",{"class":"vt"},wrap,(D.dim===3?v+" view: ":"")+ax[2]+" right, "+ax[3]+" up ("+D.load_units[0]+")");
  var ox=(w-s*(lim[1]-lim[0]))/2,oy=(hh-s*(lim[3]-lim[2]))/2;
  views.push({name:v,svg:svg,ax:ax,s:s,hs:D.symbol*s,
   P:function(p){return [ox+(p[ax[0]]-lim[0])*s,oy+(lim[3]-p[ax[1]])*s];},
   V:function(u){return [u[ax[0]]*s,-u[ax[1]]*s];}});});})();
function pts(ps,V){return ps.map(function(p){return V.P(p).join(",");}).join(" ");}
function zig(a,b,wd){var dx=b[0]-a[0],dy=b[1]-a[1],L=Math.hypot(dx,dy);if(L<1e-9)return [a,b];
 var t=[dx/L,dy/L],n=[-t[1],t[0]],out=[a];for(var k=0;k<=12;k++){var s=0.2+0.6*k/12,o=(k===0||k===12)?0:(k%2?wd:-wd);
  out.push([a[0]+s*dx+o*n[0],a[1]+s*dy+o*n[1]]);}out.push(b);return out;}
function arrow(g,a,b,colour,at){var dx=b[0]-a[0],dy=b[1]-a[1],L=Math.hypot(dx,dy);if(L<1e-6)return;
 var ux=dx/L,uy=dy/L,k=Math.min(10,0.5*L);
 var e=el("line",{x1:a[0],y1:a[1],x2:b[0]-ux*k*0.8,y2:b[1]-uy*k*0.8,stroke:colour,"stroke-width":2},g);
 for(var n in at)e.setAttribute(n,at[n]);
 el("polygon",{points:[b[0],b[1],b[0]-ux*k-uy*k*0.4,b[1]-uy*k+ux*k*0.4,b[0]-ux*k+uy*k*0.4,b[1]-uy*k-ux*k*0.4].join(" "),
 fill:colour},g);}
// a rotary element at its joint, as drawing.py's _draw_coil draws it: a torsion spring as a spiral of two and a half
// turns from 0.55 h out to 1.6 h, a rotary damper as a 200-degree arc of radius 3 h with a dashpot across its top
function coil(g,V,it,h){var c=V.P(it[1]),P=function(x,y){return [c[0]+x,c[1]-y];},p=[],k;
 var at={fill:"none","stroke-width":1.3,"data-kind":"coil","data-coil":it[2],"data-name":it[0],"data-xy":xy(it[1])};
 if(it[2]==="spring"){for(k=0;k<=120;k++){var f=5*Math.PI*k/120,r=h*(0.55+1.05*k/120);p.push(P(r*Math.cos(f),r*Math.sin(f)));}
  at.stroke="#ff7f0e";at.points=p.map(function(q){return q.join(",");}).join(" ");el("polyline",at,g);return;}
 var R=3*h;for(k=0;k<=60;k++){var a=(-10+200*k/60)*Math.PI/180;p.push(P(R*Math.cos(a),R*Math.sin(a)));}
 at.stroke="#8c564b";at.points=p.map(function(q){return q.join(",");}).join(" ");el("polyline",at,g);
 var s={stroke:"#8c564b",fill:"none","stroke-width":1.3};
 el("polyline",Object.assign({points:[P(-0.5*h,R-0.45*h),P(-0.5*h,R+0.45*h)].join(" ")},s),g);
 el("polyline",Object.assign({points:[P(0.7*h,R+0.6*h),P(-0.2*h,R+0.6*h),P(-0.2*h,R-0.6*h),P(0.7*h,R-0.6*h)].join(" ")},s),g);}
function drawView(V,pose){var svg=V.svg,hs=V.hs;svg.innerHTML="";var g=el("g",{},svg);
 pose.sliders.forEach(function(it){var p=V.P(it[0]),d=V.V(it[1]),L=Math.hypot(d[0],d[1]);if(L<1e-9)return;var u=[d[0]/L,
 d[1]/L],n=[-u[1],u[0]];
  [-1,1].forEach(function(sg){el("line",{x1:p[0]-4*hs*u[0]+sg*0.85*hs*n[0],y1:p[1]-4*hs*u[1]+sg*0.85*hs*n[1],
   x2:p[0]+4*hs*u[0]+sg*0.85*hs*n[0],y2:p[1]+4*hs*u[1]+sg*0.85*hs*n[1],stroke:"#888"},g);});
  var c=[[-1.6,-0.6],[1.6,-0.6],[1.6,0.6],[-1.6,
 0.6]].map(function(k){return (p[0]+hs*(k[0]*u[0]+k[1]*n[0]))+","+(p[1]+hs*(k[0]*u[1]+k[1]*n[1]));});
  el("polygon",{points:c.join(" "),fill:"#bfbfbf",stroke:"#333","data-kind":"slider","data-xy":xy(it[0])},g);});
 [["grounds",1],["anchors",0.7]].forEach(function(kd){pose[kd[0]].forEach(function(p){var a=V.P(p),s=hs*kd[1];
  el("polygon",{points:[a[0],a[1],a[0]-1.2*s,a[1]+2*s,a[0]+1.2*s,a[1]+2*s].join(" "),fill:"#d9d9d9",stroke:"#333",
   "data-kind":kd[0]==="grounds"?"ground":"anchor","data-xy":xy(p)},g);
  el("line",{x1:a[0]-2*s,y1:a[1]+2*s,x2:a[0]+2*s,y2:a[1]+2*s,stroke:"#333","stroke-width":1.5},g);});});
 pose.springs.forEach(function(it){el("polyline",{points:zig(V.P(it[1]),V.P(it[2]),
 0.7*hs).map(function(p){return p.join(",");}).join(" "),
  fill:"none",stroke:"#ff7f0e","stroke-width":1.4,"data-kind":"spring","data-name":it[0],"data-xy":xys([it[1],it[2]])},g);});
 (pose.slots||[]).forEach(function(it){var a=V.P(it[1]),b=V.P(it[2]);el("line",{x1:a[0],y1:a[1],x2:b[0],y2:b[1],
  stroke:"#555","stroke-width":7,"stroke-opacity":0.35,"stroke-linecap":"round","data-kind":"slot","data-name":it[0],
  "data-xy":xys([it[1],it[2]])},g);});
 pose.dampers.forEach(function(it){var a=V.P(it[1]),b=V.P(it[2]);el("line",{x1:a[0],y1:a[1],x2:b[0],y2:b[1],stroke:"#8c564b",
  "stroke-width":3,"stroke-dasharray":"8 3","data-kind":"damper","data-name":it[0],"data-xy":xys([it[1],it[2]])},g);});
 pose.actuators.forEach(function(it){var a=V.P(it[1]),b=V.P(it[2]);el("line",{x1:a[0],y1:a[1],x2:b[0],y2:b[1],stroke:"#6a3d9a",
  "stroke-width":4,"data-kind":"actuator","data-name":it[0],"data-xy":xys([it[1],it[2]])},g);});
 (pose.coils||[]).forEach(function(it){coil(g,V,it,hs);});
 pose.bars.forEach(function(it){var b=D.bodies[it[0]];
  el("polyline",{points:pts(it[1],V),fill:"none",stroke:b.colour,"stroke-width":C?5:6,"stroke-linecap":"round",
   "stroke-linejoin":"round","data-kind":"bar","data-body":b.name,"data-xy":xys(it[1])},g);});
 pose.axes.forEach(function(it){var u=V.V(it[2]),L=Math.hypot(u[0],u[1]);if(L<1e-9*V.s)return;var a=V.P(it[1]),k=3*hs/L;
  el("line",{x1:a[0]-k*u[0],y1:a[1]-k*u[1],x2:a[0]+k*u[0],y2:a[1]+k*u[1],stroke:"#555","stroke-dasharray":"6 2 1 2"},g);});
 pose.pins.concat(pose.grounds,pose.sliders.map(function(s){return s[0];})).forEach(function(p){var a=V.P(p);
  el("circle",{cx:a[0],cy:a[1],r:Math.max(2,0.45*hs),fill:"#fff",stroke:"#000","stroke-width":1.2,"data-kind":"pin",
 "data-xy":xy(p)},g);});
 (pose.contacts||[]).forEach(function(it){var a=V.P(it[1]),s=Math.max(2.5,0.6*hs);
  el("rect",{x:a[0]-s,y:a[1]-s,width:2*s,height:2*s,fill:"#222",stroke:"#222","data-kind":"contact","data-name":it[0],
   "data-xy":xy(it[1])},g,undefined);});
 pose.forces.forEach(function(it){var a=V.P(it[1]),f=V.V(it[2]),sc=D.force_scale;
  arrow(g,a,[a[0]+sc*f[0],a[1]+sc*f[1]],"#d62728",{"data-kind":"force","data-name":it[0],"data-xy":xys([it[1],it[2]])});});
 pose.moments.forEach(function(it){var a=V.P(it[1]),m=(typeof it[2]==="number")?it[2]:V.ax[4]*it[2][3-V.ax[0]-V.ax[1]];
  if(m===0)return;var r=2.2*hs,t0=-Math.PI/4,t1=5*Math.PI/4,p=[];for(var k=0;k<=30;k++){var t=t0+(t1-t0)*k/30;
 p.push([a[0]+r*Math.cos(t),a[1]-r*Math.sin(t)]);}
  if(m<0)p.reverse();el("polyline",{points:p.slice(0,-2).map(function(q){return q.join(",");}).join(" "),fill:"none",
 stroke:"#d62728",
   "stroke-width":1.6,"data-kind":"moment","data-name":it[0],"data-xy":xy(it[1])},g);arrow(g,p[p.length-4],p[p.length-1],
 "#d62728",{});});}
// ---------------------------------------------------------------- values and loads
function word(br,r){var n=br.n_unstable[r];if(br.labels[r]==="LP"||br.labels[r]==="NSF")return "fold";
 return n<0?"":(n===0?"stable":"unstable ("+n+")");}
function drawTables(b,r){var br=B[b],t=q(".values");t.innerHTML="";
 var hd=h("tr",{},t);h("th",{},hd,"variable");h("th",{},hd,"value");h("th",{},hd,"unit");
 Object.keys(br.columns).forEach(function(n){var tr=h("tr",{"data-name":n},t),u=unit(b,n);h("td",{},tr,n);
  h("td",{"class":"n","data-value":String(br.columns[n][r])},tr,fmt(shown(b,n,br.columns[n][r])));h("td",{},tr,
 u==="rad"?"deg":u);});
 var L=q(".loads");L.innerHTML="";if(!br.poses)return;var pose=br.cycle?br.poses[r][0]:br.poses[r],rows=[];
 var fu=D.load_units[1],mu=D.load_units[2];
 pose.forces.forEach(function(it){var m=Math.hypot.apply(null,it[2]);rows.push([it[0],load(m,fu),
 "("+it[2].map(fmt).join(", ")+") "+fu]);});
 pose.moments.forEach(function(it){var v=it[2];rows.push([it[0],(typeof v==="number")?load(v,
 mu):load(Math.hypot.apply(null,v),mu),
  (typeof v==="number")?"counter-clockwise +":"("+v.map(fmt).join(", ")+") "+mu]);});
 pose.actuators.forEach(function(it){rows.push([it[0],load(Math.abs(it[3]),fu),
 it[3]>0?"tension":(it[3]<0?"compression":"unloaded")]);});
 if(!rows.length)return;var th=h("tr",{},L);h("th",{},th,"load");h("th",{},th,"magnitude");h("th",{},th,"");
 rows.forEach(function(rw){var tr=h("tr",{"class":"load"},L);rw.forEach(function(c,i){h("td",{"class":i===1?"n":""},tr,c);});});}
// ---------------------------------------------------------------- selection
var play=null;
function show(b,r){cur={b:b,r:r};var br=B[b];if(play){clearInterval(play);play=null;}
 if(br.cycle)period(b,r);else if(br.poses)views.forEach(function(V){drawView(V,br.poses[r]);});
 var sp=br.special.filter(function(s){return s.row===r;}).map(function(s){return s.tag;}).join(", ");
 var st=q(".status");st.textContent=(B.length>1?br.name+", ":"")+"row "+br.rows[r]+(sp?": "+sp:"")+(word(br,
 r)?" \u2014 "+word(br,r):"");
 st.setAttribute("data-branch",b);st.setAttribute("data-row",r);st.style.color=word(br,r)==="stable"?"#2a7a2a":(word(br,
 r).indexOf("unstable")===0?"#b22222":"#333");
 drawTables(b,r);placeCursor();
 root.querySelectorAll(".sp button").forEach(function(e){
  e.className=(+e.getAttribute("data-branch")===b&&+e.getAttribute("data-row")===r)?"on":"";});}
// one period of a cycle row: the mechanism's poses played in turn (two seconds a period), or an ODE's phase portrait
function period(b,r){var br=B[b],T=br.columns.period[r],n=br.cycle.frames,k=0,st=q(".views");
 if(br.poses){var step=function(){views.forEach(function(V){drawView(V,br.poses[r][k]);V.svg.setAttribute("data-frame",k);
   V.svg.setAttribute("data-t",String(T*k/n));});k=(k+1)%n;};step();play=setInterval(step,2000/n);return;}
 views.forEach(function(V){V.svg.innerHTML="";});var old=st.querySelector(".phase");if(old)st.removeChild(old);
 if(!br.orbits)return;var O=br.orbits[r],S=br.cycle.orbit_states,w=C?330:460,hh=C?280:390,m=56;
 var ia=0,ib=S.length>1?1:-1,val=function(p,i){return i<0?T*O.indexOf(p)/n:p[i];};
 var xs=O.map(function(p){return val(p,ia);}),ys=O.map(function(p){return val(p,ib);});
 var x0=Math.min.apply(null,xs),x1=Math.max.apply(null,xs),y0=Math.min.apply(null,ys),y1=Math.max.apply(null,ys);
 if(!(x1>x0)){x0-=1e-9;x1+=1e-9;}if(!(y1>y0)){y0-=1e-9;y1+=1e-9;}
 var sx=function(v){return m+(v-x0)/(x1-x0)*(w-m-10);},sy=function(v){return hh-m+(y0-v)/(y1-y0)*(hh-m-10);};
 var wrap=h("div",{"class":"phase"},st),svg=el("svg",{width:w,height:hh,viewBox:"0 0 "+w+" "+hh,"class":"phase-portrait"},wrap);
 var g=el("g",{"font-size":"11",fill:"#333"},svg);el("rect",{x:m,y:10,width:w-m-10,height:hh-m-10,fill:"none",stroke:"#888"},g);
 ticks(x0,x1).forEach(function(v){el("text",{x:sx(v),y:hh-m+14,"text-anchor":"middle"},g,fmt(v));});
 ticks(y0,y1).forEach(function(v){el("text",{x:m-3,y:sy(v)+4,"text-anchor":"end"},g,fmt(v));});
 el("text",{x:(m+w)/2,y:hh-8,"text-anchor":"middle"},g,ib<0?"t (s)":axisLabel(S[ia]));
 el("text",{x:12,y:hh/2,"text-anchor":"middle",transform:"rotate(-90 12 "+hh/2+")"},g,axisLabel(S[ib<0?ia:ib]));
 el("polygon",{points:xs.map(function(v,i){return sx(v)+","+sy(ys[i]);}).join(" "),fill:"none",stroke:"#1f77b4",
  "stroke-width":1.6,"data-kind":"orbit","data-xy":O.map(function(p){return p.join(" ");}).join(";")},svg);
 h("div",{"class":"vt"},wrap,"phase portrait of the orbit, one period T = "+fmt(T)+" s");
 var dot=el("circle",{r:4,fill:"#ff7f0e","class":"mcx-now"},svg);
 var step2=function(){dot.setAttribute("cx",sx(xs[k]));dot.setAttribute("cy",sy(ys[k]));dot.setAttribute("data-frame",k);
  k=(k+1)%n;};step2();play=setInterval(step2,2000/n);}
function fix(b,r){fixed={b:b,r:r};if(+bsel.value!==b)bsel.value=b;slider.max=B[b].rows.length-1;slider.value=r;show(b,r);}
q(".title").textContent=D.title;
var notes=B.filter(function(br){return br.note;}).map(function(br){return br.name+": "+br.note;});
if(!D.bodies.length)notes.push(B.some(function(br){return br.orbits;})?"no mechanism to draw: a cycle row shows its "+
 "orbit's phase portrait":"no mechanism to draw: the diagram only");q(".notes").textContent=notes.join("; ");
drawDiagram();
var first=B[0].special.filter(function(s){return s.label!=="EP";}).concat(B[0].special)[0];
fix(0,first?first.row:0);  // the first fold, cusp or event: the point a reader looks at first
root.setAttribute("data-ready","1");
})();
"""


def render(data_json: str, token: str, *, title: str = "", compact: bool = False) -> str:
    """The page: ``data_json`` (the JSON text of :func:`.explore.page_data`) embedded under the
    element id ``token``; ``compact`` makes the views smaller (a notebook's output cell)."""
    data = data_json.replace("<", "\\u003c")  # nothing in the JSON can close the script element
    if compact:
        data = data[:-1] + ',"compact":true}'
    title = html.escape(title or "mechcont")
    css = _CSS.replace("TOKEN", token)
    js = _JS.replace('"TOKEN"', f'"{token}"')
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{title} explorer</title></head><body>\n"
            f"<div id=\"{token}\" class=\"mcx{' compact' if compact else ''}\"><style>{css}</style>{_BODY}"
            f"<script type=\"application/json\" class=\"mcx-data\">{data}</script>\n<script>{js}</script></div>\n"
            "</body></html>\n")

