local x, y, z = 1, 0, 0
for i = 1, 30000 do
  for j = 1, 100 do
    x = (x * 3 + j) % 1000
    if x > 500 then y = y + 1 else z = (z + 1) % 30000 end
    if y > 10000 then y = y - 10000 end
  end
end
print(x, y, z)
