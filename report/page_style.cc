#include "report/page_style.h"

namespace lsds::report {

Html PageStyle() {
  return Html::Markup(R"CSS(
body{font:13px/1.4 system-ui,sans-serif;margin:0 16px 32px;background:#f4f4f2;color:#222}
h1{font-size:20px;margin:14px 0 4px}h2{font-size:16px;margin:22px 0 6px;border-bottom:1px solid #ccc}
h3{font-size:13px;margin:8px 0 4px}nav a{margin-right:12px}
.help,.note{color:#555;margin:2px 0 8px}.note{font-size:12px}
.filter label{margin-right:12px;white-space:nowrap;cursor:pointer}
.swatch{display:inline-block;width:10px;height:10px;margin:0 3px 0 2px;border:1px solid #444}
.sheet{display:flex;flex-wrap:wrap;gap:10px}
.card{margin:0;background:#fff;border:1px solid #ccc;padding:4px;cursor:pointer;max-width:340px}
.card:hover{border-color:#36c}.card.hit{outline:3px solid #d33}
.card img{display:block}.card figcaption{font-size:11.5px;color:#333;margin-top:3px}
.tag{background:#36c;color:#fff;border-radius:3px;padding:0 4px;font-size:10px}
.strip{display:flex;flex-wrap:wrap;gap:8px}.strip figure{margin:0;background:#fff;border:1px solid #ccc;padding:4px}
.strip figcaption{font-size:11.5px;max-width:320px}
.strip img.bar{display:block;margin-top:3px}.strip img.wheel{vertical-align:middle;margin:0 4px}
.range{display:flex;justify-content:space-between;font-size:11px}
.failed{color:#a00;padding:8px;max-width:300px}
.plots{display:flex;flex-wrap:wrap;gap:12px}.plot{background:#fff;border:1px solid #ccc;padding:4px 8px}
svg.hist text{font-size:10px;fill:#333}svg.hist .bar{fill:#4a7bd0}svg.hist .bar.warn{fill:#d04a4a}
svg.hist .grid{stroke:#e4e4e4}svg.hist .axis{stroke:#333}
table{border-collapse:collapse;font-size:12px;background:#fff}td,th{border:1px solid #ddd;padding:2px 6px;text-align:left}
.findings tr.error td{background:#fbe3e3}.findings tr.warning td{background:#fdf3d6}
.verdict.pass{color:#080}.verdict.fail{color:#b00}
#overlay{position:fixed;inset:0;background:rgba(0,0,0,.55);display:flex;align-items:flex-start;justify-content:center;overflow:auto;z-index:10}
#overlay[hidden]{display:none}
#overlay .panel{background:#f4f4f2;margin:24px;padding:12px;max-width:95vw}
#overlay img.big{width:640px;max-width:90vw;height:auto;image-rendering:pixelated}
table.mixing td{text-align:right}.meter{display:inline-block;height:9px;background:#d04a4a;vertical-align:middle}
footer{margin-top:28px;color:#777}
)CSS");
}

Html PageScript() {
  return Html::Markup(R"JS(
(function(){
  var boxes=Array.prototype.slice.call(document.querySelectorAll('.filter input'));
  var cards=Array.prototype.slice.call(document.querySelectorAll('.card'));
  function apply(){
    var on={};
    boxes.forEach(function(b){if(b.checked)on[b.getAttribute('data-class')]=true;});
    cards.forEach(function(c){
      var list=c.getAttribute('data-classes');
      var classes=list?list.split(' '):[''];
      var show=classes.some(function(x){return on[x]===true;});
      c.style.display=show?'':'none';
    });
  }
  boxes.forEach(function(b){b.addEventListener('change',apply);});
  var overlay=document.getElementById('overlay');
  var body=document.getElementById('overlay-body');
  function open(card){
    body.innerHTML='';
    var title=document.createElement('h3');
    title.textContent='frame '+card.getAttribute('data-frame');
    body.appendChild(title);
    var strip=document.getElementById('layers-'+card.getAttribute('data-frame'));
    if(strip){
      body.appendChild(strip.querySelector('.strip').cloneNode(true));
    }else{
      var img=card.querySelector('img');
      if(img){var big=img.cloneNode(false);big.className='big';body.appendChild(big);}
    }
    var detail=card.querySelector('.detail');
    if(detail){var copy=detail.cloneNode(true);copy.hidden=false;body.appendChild(copy);}
    overlay.hidden=false;
  }
  function close(){overlay.hidden=true;}
  cards.forEach(function(c){c.addEventListener('click',function(){open(c);});});
  document.getElementById('close').addEventListener('click',close);
  overlay.addEventListener('click',function(e){if(e.target===overlay)close();});
  document.addEventListener('keydown',function(e){if(e.key==='Escape')close();});
  Array.prototype.slice.call(document.querySelectorAll('a[data-goto]')).forEach(function(a){
    a.addEventListener('click',function(){
      var c=document.getElementById('frame-'+a.getAttribute('data-goto'));
      if(!c)return;
      c.style.display='';
      c.classList.add('hit');
      setTimeout(function(){c.classList.remove('hit');},2500);
    });
  });
  document.body.setAttribute('data-report-ready','1');
})();
)JS");
}

}  // namespace lsds::report
