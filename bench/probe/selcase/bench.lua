local st, n, x = 0, 0, 1
for i = 1, 2000000 do
  x = (x * 75 + 74) % 65537
  if st == 0 then
    if x > 30000 then st = 1 else n = n + 1 end
  elseif st == 1 then
    if (x & 7) == 3 then st = 2 end
  elseif st == 2 then
    n = n + 2; st = 3
  else
    if x < 1000 then st = 0 else st = 1 end
  end
end
print(n, st)
